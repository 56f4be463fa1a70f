// One name table per enum (engine/core/enum_names.h): printed and parsed from the same rows, and the
// ArgParser's choice options built on them.
#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>

#include "engine/core/args.h"
#include "engine/core/enum_names.h"
#include "engine/core/error.h"
#include "engine/core/json.h"

using namespace cumulo;

namespace {

enum class Shape { Round, Square, Flat };
// Two names of one value: the first is the one printed ("disc" is accepted).
constexpr std::array kShapeNames{EnumName<Shape>{Shape::Round, "round"}, EnumName<Shape>{Shape::Round, "disc"},
                                 EnumName<Shape>{Shape::Square, "square"}, EnumName<Shape>{Shape::Flat, "flat"}};

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

bool parse(ArgParser& p, std::vector<const char*> argv) {
  return p.parse(int(argv.size()), const_cast<char**>(argv.data()));
}

}  // namespace

TEST(EnumNames, PrintAndParseFromOneTable) {
  EXPECT_STREQ(name_of(kShapeNames, Shape::Square), "square");
  EXPECT_STREQ(name_of(kShapeNames, Shape::Round), "round");  // the first row of the value
  EXPECT_EQ(parse_name(kShapeNames, "disc"), Shape::Round);
  EXPECT_FALSE(parse_name(kShapeNames, "Square"));  // exact spelling only
  EXPECT_EQ(names_list(kShapeNames), "round, disc, square or flat");
  EXPECT_EQ(names_choice(kShapeNames), "round|disc|square|flat");
  const std::string e = error_of([] { parse_name_or_fail(kShapeNames, "--shape", "oval\n"); });
  EXPECT_EQ(e, "--shape: expected round, disc, square or flat, got \"oval\\n\"");
}

TEST(EnumNames, ChoiceOptionsParseOnceAndNameEveryValue) {
  Shape shape = Shape::Flat;
  bool on = true;
  std::optional<bool> preset_on;
  ArgParser p("cumulo test", "choices");
  p.choice("--shape", kShapeNames, "a shape", &shape).on_off("--light", "on or off", &on);
  p.choice("--shadows", kOnOffNames, "preset", "on, off or the preset's", &preset_on);
  ASSERT_TRUE(parse(p, {"test", "--shape", "disc", "--light=off", "--shadows", "on"}));
  EXPECT_EQ(shape, Shape::Round);
  EXPECT_FALSE(on);
  EXPECT_EQ(preset_on, true);
  ArgParser q("cumulo test", "choices");
  q.choice("--shadows", kOnOffNames, "preset", "", &preset_on);
  ASSERT_TRUE(parse(q, {"test", "--shadows", "preset"}));
  EXPECT_FALSE(preset_on);  // the word that leaves it to someone else
  const std::string help = p.help();
  EXPECT_NE(help.find("round|disc|square|flat"), std::string::npos) << help;
  EXPECT_NE(help.find("on|off|preset"), std::string::npos) << help;
  ArgParser r("cumulo test", "choices");
  r.choice("--shape", kShapeNames, "", &shape).choice("--shadows", kOnOffNames, "preset", "", &preset_on);
  EXPECT_EQ(error_of([&] { parse(r, {"test", "--shape", "cube"}); }),
            "--shape: expected round, disc, square or flat, got \"cube\"");
  EXPECT_EQ(error_of([&] { parse(r, {"test", "--shadows", "yes"}); }), "--shadows: expected on, off or preset, got \"yes\"");
}

TEST(EnumNames, JsonValuesReadThroughTheTableNameThePlace) {
  const JsonDocument doc = parse_json_text(R"({"a": "square", "b": "cube"})", "shapes.json");
  EXPECT_EQ(doc.view()["a"].as_name(kShapeNames), Shape::Square);
  const std::string e = error_of([&] { doc.view()["b"].as_name(kShapeNames); });
  EXPECT_NE(e.find("shapes.json"), std::string::npos) << e;
  EXPECT_NE(e.find("$.b"), std::string::npos) << e;
  EXPECT_NE(e.find("round"), std::string::npos) << e;
}
