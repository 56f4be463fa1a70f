#include "editor/model/weather_params.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "editor/model/weather_document.h"
#include "engine/core/file_io.h"
#include "modules/clouds/weather/weather_state.h"
#include "tests/editor/editor_test_support.h"

namespace cumulo::editor {
namespace {

TEST(WeatherParams, EveryShippedStateRoundTripsThroughTheTable) {
  int states = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::shipped_weather())) {
    if (e.path().extension() != ".json") continue;
    ++states;
    const std::string text = read_file_text(e.path());
    const Json original = Json::parse(text);
    Json copy = original;
    for (const ParamInfo& p : weather_params()) {
      Json v;
      try {
        v = get_param(original, p.path);
      } catch (const Error&) {
        EXPECT_FALSE(p.default_value.is_null()) << e.path() << " leaves out the required " << p.path;
        continue;  // an optional key the state leaves out
      }
      EXPECT_EQ(check_param_value(p, v), std::nullopt) << e.path() << " " << p.path;
      set_param(copy, p.path, normalize_param_value(p, v));
    }
    EXPECT_EQ(copy, original) << e.path();
    // Saving an unchanged state rewrites the shipped bytes exactly: clean diffs.
    EXPECT_EQ(weather_state_text(copy), text) << e.path();
    // The table covers every key the loader reads (all but $schema and the optional png).
    const clouds::weather::WeatherState s = clouds::weather::load_weather_state(e.path());
    EXPECT_FLOAT_EQ(get_param(original, "lighting.silver.spread").get<float>(), s.lighting.silver_spread);
  }
  EXPECT_EQ(states, 5);
}

TEST(WeatherParams, TableIsConsistent) {
  const auto& groups = weather_param_groups();
  for (const ParamInfo& p : weather_params()) {
    EXPECT_EQ(find_param(p.path), &p);
    EXPECT_FALSE(p.label.empty());
    EXPECT_FALSE(p.tooltip.empty()) << p.path;
    EXPECT_NE(std::find(groups.begin(), groups.end(), p.group), groups.end()) << p.path;
    if (p.kind != ParamKind::Text) {
      EXPECT_LT(p.min, p.max) << p.path;
    }
  }
  EXPECT_EQ(find_param("lighting"), nullptr);
  EXPECT_EQ(find_param("nope"), nullptr);
  EXPECT_EQ(find_param("coverage")->kind, ParamKind::Float);
  EXPECT_EQ(find_param("cloud_map.procedural.octaves")->kind, ParamKind::Int);
  EXPECT_EQ(find_param("cloud_map.procedural.octaves")->max, 8);
  EXPECT_EQ(find_param("wind.direction")->kind, ParamKind::Vec3);
  EXPECT_EQ(find_param("lighting.absorption")->min, 1e-5);
}

TEST(WeatherParams, GetAndSetByDottedPath) {
  Json j = {{"lighting", {{"phase", {{"forward", 0.8}}}}}};
  EXPECT_EQ(get_param(j, "lighting.phase.forward"), 0.8);
  try {
    get_param(j, "lighting.silver.spread");
    FAIL() << "expected a throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lighting.silver.spread"), std::string::npos) << e.what();
  }
  EXPECT_THROW(get_param(j, "lighting..phase"), Error);
  set_param(j, "lighting.silver.spread", 0.25);
  EXPECT_EQ(j["lighting"]["silver"]["spread"], 0.25);
  EXPECT_EQ(j["lighting"]["phase"]["forward"], 0.8);
  EXPECT_THROW(set_param(j, "lighting.phase.forward.x", 1), Error);  // inside a number
}

TEST(WeatherParams, ValueChecksNameTheRange) {
  const ParamInfo& cov = *find_param("coverage");
  EXPECT_EQ(check_param_value(cov, 0.5), std::nullopt);
  EXPECT_EQ(*check_param_value(cov, 1.5), "1.5 is out of range [0, 1]");
  EXPECT_NE(check_param_value(cov, "x")->find("expected a number"), std::string::npos);
  const ParamInfo& oct = *find_param("cloud_map.procedural.octaves");
  EXPECT_EQ(check_param_value(oct, 3), std::nullopt);
  EXPECT_EQ(check_param_value(oct, 3.0), std::nullopt);
  EXPECT_NE(check_param_value(oct, 3.5), std::nullopt);
  EXPECT_EQ(*check_param_value(oct, 9), "9 is out of range [1, 8]");
  const ParamInfo& dir = *find_param("wind.direction");
  EXPECT_EQ(check_param_value(dir, Json::array({1, 0, 0.5})), std::nullopt);
  EXPECT_NE(check_param_value(dir, Json::array({1, 0})), std::nullopt);
  EXPECT_NE(check_param_value(dir, Json::array({1, "a", 0})), std::nullopt);
  EXPECT_NE(check_param_value(*find_param("description"), 3), std::nullopt);
}

TEST(WeatherParams, SliderFloatsAreStoredAsShortDecimals) {
  const ParamInfo& cov = *find_param("coverage");
  const Json v = normalize_param_value(cov, Json(0.45f));
  EXPECT_EQ(v.get<double>(), 0.45);
  EXPECT_EQ(v.dump(), "0.45");
  EXPECT_EQ(normalize_param_value(*find_param("cloud_map.procedural.seed"), Json(7.0)).dump(), "7");
  EXPECT_EQ(normalize_param_value(*find_param("wind.direction"), Json::array({0.1f, 1, 0})).dump(), "[0.1,1,0]");
}

}  // namespace
}  // namespace cumulo::editor
