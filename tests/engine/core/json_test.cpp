#include <gtest/gtest.h>

#include "engine/core/json.h"

using namespace cumulo;

static std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Json, SyntaxErrorNamesFileLineAndColumn) {
  std::string msg = error_of([] { parse_json_text("{\n  \"a\": 1,\n  \"b\": ]\n}", "level.json"); });
  EXPECT_NE(msg.find("level.json:3:8"), std::string::npos) << msg;
}

TEST(Json, WrongTypeNamesJsonPath) {
  auto doc = parse_json_text(R"({"entities":[{"t":{"pos":[1,2,"x"]}}]})", "l.json");
  std::string msg = error_of([&] { doc.view()["entities"].at(0)["t"]["pos"].as_vec3(); });
  EXPECT_NE(msg.find("l.json: $.entities[0].t.pos[2]: expected a number, got string"), std::string::npos) << msg;
}

TEST(Json, MissingMemberAndDefaults) {
  auto doc = parse_json_text(R"({"a":{"x":2}})", "f.json");
  auto a = doc.view()["a"];
  EXPECT_EQ(a.get<int>("x"), 2);
  EXPECT_EQ(a.get<int>("y", 7), 7);
  std::string msg = error_of([&] { a.get<int>("y"); });
  EXPECT_NE(msg.find("f.json: $.a: missing required member \"y\""), std::string::npos) << msg;
}

TEST(Json, RangesAndEnums) {
  auto doc = parse_json_text(R"({"v":5,"e":"cumulus"})", "f.json");
  EXPECT_THROW(doc.view()["v"].as_float_in(0, 1), Error);
  EXPECT_EQ(doc.view()["e"].as_enum({"stratus", "cumulus"}), 1u);
  EXPECT_THROW(doc.view()["e"].as_enum({"stratus"}), Error);
  EXPECT_THROW(doc.view()["v"].as<std::string>(), Error);
  EXPECT_THROW(doc.view()["e"].as<uint32_t>(), Error);
}
