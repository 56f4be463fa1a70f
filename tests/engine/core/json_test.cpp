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

// ---- outside numbers, depth and echoed values (issue: hardening every loader) ----------------------

TEST(Json, NumberOverflowingADoubleNamesFileLineAndPath) {
  // nlohmann throws out_of_range.406 for this; we report it like any other bad value.
  std::string text = "{\n  \"entities\": [{\"Camera\": {\"far\": 1e999999}}]\n}";
  std::string msg = error_of([&] { parse_json_text(text, "level.json"); });
  EXPECT_NE(msg.find("level.json:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("$.entities[0].Camera.far"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1e999999"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("json.exception"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_THROW(check_json_text(text, "level.json"), Error);
}

TEST(Json, NumbersMustFitTheTypeTheyAreStoredIn) {
  JsonDocument doc = parse_json_text(
      R"({"far": 1e39, "ok": 3e38, "big": 4294967312, "neg": -1, "huge": 18446744073709551615, "half": 2.5,
          "whole": 7.0, "i64max": 9223372036854775807})",
      "n.json");
  JsonView v = doc.view();
  std::string msg = error_of([&] { v["far"].as<float>(); });
  EXPECT_NE(msg.find("n.json: $.far: 1e+39 does not fit a 32-bit float"), std::string::npos) << msg;
  EXPECT_FLOAT_EQ(v["ok"].as<float>(), 3e38f);
  EXPECT_DOUBLE_EQ(v["far"].as<double>(), 1e39);
  msg = error_of([&] { v["big"].as<uint32_t>(); });
  EXPECT_NE(msg.find("$.big: 4294967312 does not fit an unsigned 32-bit integer"), std::string::npos) << msg;
  EXPECT_THROW(v["big"].as<int>(), Error);
  EXPECT_EQ(v["big"].as<int64_t>(), 4294967312ll);
  EXPECT_THROW(v["neg"].as<uint64_t>(), Error);
  EXPECT_THROW(v["neg"].as<uint32_t>(), Error);
  EXPECT_EQ(v["huge"].as<uint64_t>(), 18446744073709551615ull);  // exact, not through a double
  EXPECT_THROW(v["huge"].as<int64_t>(), Error);
  EXPECT_EQ(v["i64max"].as<int64_t>(), 9223372036854775807ll);
  EXPECT_THROW(v["half"].as<int>(), Error);
  EXPECT_EQ(v["whole"].as<int>(), 7);
  // Vectors go through the same rule, naming the element.
  JsonDocument vec = parse_json_text(R"({"p": [0, 1e39, 0]})", "v.json");
  msg = error_of([&] { vec.view()["p"].as_vec3(); });
  EXPECT_NE(msg.find("v.json: $.p[1]:"), std::string::npos) << msg;
}

TEST(Json, DeepNestingIsRefusedBeforeAnyParserRecurses) {
  std::string deep = "{\"a\": " + std::string(20000, '[') + std::string(20000, ']') + "}";
  std::string msg = error_of([&] { parse_json_text(deep, "deep.json"); });
  EXPECT_NE(msg.find("deep.json:1:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("nested deeper than 256 levels"), std::string::npos) << msg;
  EXPECT_THROW(check_json_text(deep, "deep.json"), Error);
  // Brackets inside strings do not count; 256 levels are fine.
  std::string ok = std::string(255, '[') + "\"" + std::string(1000, '[') + "\"" + std::string(255, ']');
  EXPECT_NO_THROW(parse_json_text(ok, "ok.json"));
}

TEST(Json, LongValuesAreCutInMessages) {
  std::string big(2 << 20, 'x');
  JsonDocument doc = parse_json_text("{\"e\": \"" + big + "\", \"" + big + "\": 1}", "big.json");
  std::string msg = error_of([&] { doc.view()["e"].as_enum({"a", "b"}); });
  EXPECT_LT(msg.size(), 400u) << msg.substr(0, 400);
  EXPECT_NE(msg.find("(2097152 bytes)"), std::string::npos) << msg;
  msg = error_of([&] { doc.view()[big + "y"]; });
  EXPECT_LT(msg.size(), 400u);
  EXPECT_NE(msg.find("missing required member"), std::string::npos) << msg;
}
