// Weather states (issue 9): every shipped state loads and agrees with the shipped schema; malformed
// states are refused with the file, the JSON path and what was expected; blends are parameter lerps.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/json.h"
#include "modules/clouds/weather/weather_library.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;
using namespace cumulo::clouds::weather;

namespace {

// Two states agree key by key, numbers within `eps` (a direction renormalized, a float through JSON).
void expect_near(const WeatherState& a, const WeatherState& b, double eps = 1e-6) {
  std::function<void(const Json&, const Json&, const std::string&)> walk = [&](const Json& x, const Json& y,
                                                                               const std::string& path) {
    ASSERT_EQ(x.type(), y.type()) << path;
    if (x.is_object()) {
      ASSERT_EQ(x.size(), y.size()) << path;
      for (auto& [k, v] : x.items()) walk(v, y.at(k), path + "." + k);
    } else if (x.is_array()) {
      ASSERT_EQ(x.size(), y.size()) << path;
      for (size_t i = 0; i < x.size(); ++i) walk(x[i], y[i], path + "[" + std::to_string(i) + "]");
    } else if (x.is_number()) {
      EXPECT_NEAR(x.get<double>(), y.get<double>(), eps) << path;
    } else {
      EXPECT_EQ(x, y) << path;
    }
  };
  EXPECT_EQ(a.id, b.id);
  walk(weather_state_to_json(a), weather_state_to_json(b), "$");
}

TEST(WeatherLibrary, ShipsTheFiveStatesAndRefusesAnUnknownIdListingThem) {
  const WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
  const std::vector<std::string> want{"clear", "fair_cumulus", "overcast_stratus", "storm", "stormbird"};
  EXPECT_EQ(lib.ids(), want);
  EXPECT_LT(lib.get("clear").coverage, lib.get("fair_cumulus").coverage);
  EXPECT_GT(lib.get("storm").lightning_per_minute, 0.0f);
  EXPECT_EQ(lib.get("clear").lightning_per_minute, 0.0f);
  EXPECT_LT(lib.get("overcast_stratus").cloud_type, 0.5f);  // stratus
  try {
    lib.get("drizzle");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("drizzle"), std::string::npos) << m;
    for (const std::string& id : want) EXPECT_NE(m.find(id), std::string::npos) << m;
  }
}

// The schema and the loader describe the same keys: every key of every shipped state is in the schema's
// properties (recursively), and the schema requires what the loader requires.
void check_against_schema(const Json& value, const Json& schema, const std::string& path) {
  if (!value.is_object()) return;
  ASSERT_TRUE(schema.contains("properties")) << path;
  EXPECT_EQ(schema.value("additionalProperties", true), false) << path;
  for (auto& [k, v] : value.items()) {
    ASSERT_TRUE(schema["properties"].contains(k)) << path << "." << k;
    check_against_schema(v, schema["properties"][k], path + "." + k);
  }
  for (const auto& r : schema.value("required", Json::array())) EXPECT_TRUE(value.contains(r.get<std::string>())) << path << "." << r;
}

TEST(WeatherLibrary, ShippedStatesFollowTheSchemaAndRoundTrip) {
  const JsonDocument schema = load_json_file(repo_root() / "content/schemas/weather.schema.json");
  for (const auto& e : fs::directory_iterator(WeatherLibrary::default_folder())) {
    const JsonDocument doc = load_json_file(e.path());
    check_against_schema(doc.json(), schema.json(), e.path().filename().string());
    const WeatherState s = load_weather_state(e.path());
    const JsonDocument again = parse_json_text(weather_state_to_json(s).dump(), "round trip");
    expect_near(weather_state_from_json(again.view(), s.id, e.path()), s);
  }
}

class WeatherErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_temp_dir("cumulo_weather");
    text_ = read_file_text(WeatherLibrary::default_folder() / "fair_cumulus.json");
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The error of loading fair_cumulus.json with `from` replaced by `to`.
  std::string error_of(const std::string& from, const std::string& to) {
    std::string t = text_;
    const size_t p = t.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    if (p != std::string::npos) t.replace(p, from.size(), to);
    const fs::path f = dir_ / "broken.json";
    write_file_atomic(f, t);
    try {
      load_weather_state(f);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  }
  fs::path dir_;
  std::string text_;
};

TEST_F(WeatherErrors, EachNamesTheFileThePathAndWhatWasExpected) {
  struct Case {
    const char* from;
    const char* to;
    std::vector<std::string> wants;
  };
  const Case cases[] = {
      {"\"coverage\": 0.4", "\"coverage\": 1.5", {"broken.json", "$.coverage", "1.5"}},
      {"\"coverage\": 0.4", "\"coverage\": \"most\"", {"broken.json", "$.coverage", "number"}},
      {"\"coverage\": 0.4,", "", {"broken.json", "missing required key \"coverage\""}},
      {"\"haze\": 0.1", "\"haze\": 0.1, \"fog\": 1", {"broken.json", "unknown key \"fog\"", "haze"}},
      {"\"absorption\": 0.05", "\"absorption\": -1", {"broken.json", "$.lighting.absorption"}},
      {"\"forward\": 0.8", "\"forward\": 1.2", {"broken.json", "$.lighting.phase.forward"}},
      {"\"octaves\": 4", "\"octaves\": 40", {"broken.json", "$.cloud_map.procedural.octaves", "1..8"}},
      {"\"speed\": 4", "\"speed\": 4, \"gusts\": 2", {"$.wind", "unknown key \"gusts\""}},
      {"\"procedural\": {", "\"png\": \"nowhere.png\", \"procedural\": {", {"$.cloud_map.png", "nowhere.png"}},
      {"\"coverage\": 0.4,", "\"coverage\": 0.4,,", {"broken.json:", "syntax"}},
  };
  for (const Case& c : cases) {
    const std::string m = error_of(c.from, c.to);
    for (const std::string& w : c.wants) EXPECT_NE(m.find(w), std::string::npos) << "want \"" << w << "\" in: " << m;
  }
  // A direction of zero length cannot be normalized.
  const std::string z = error_of("\"direction\": [\n      1,\n      0,\n      0.3\n    ]", "\"direction\": [0, 0, 0]");
  EXPECT_NE(z.find("$.wind.direction"), std::string::npos) << z;
}

TEST(WeatherBlend, LerpsParameterByParameterAndCrossFadesTheMap) {
  const WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
  const WeatherState& a = lib.get("fair_cumulus");
  const WeatherState& b = lib.get("storm");
  expect_near(blend(a, b, 0.0f).state, a);
  expect_near(blend(a, b, 1.0f).state, b);
  const WeatherBlend h = blend(a, b, 0.5f);
  EXPECT_FLOAT_EQ(h.state.coverage, 0.5f * (a.coverage + b.coverage));
  EXPECT_FLOAT_EQ(h.state.lighting.absorption, 0.5f * (a.lighting.absorption + b.lighting.absorption));
  EXPECT_FLOAT_EQ(h.state.lightning_per_minute, 0.5f * (a.lightning_per_minute + b.lightning_per_minute));
  EXPECT_NEAR(glm::length(h.state.wind_direction), 1.0f, 1e-5f);
  EXPECT_EQ(h.map_from, a.cloud_map);
  EXPECT_EQ(h.map_to, b.cloud_map);
  EXPECT_FLOAT_EQ(h.map_t, 0.5f);
  expect_near(blend(a, b, 7.0f).state, b);  // clamped
  // Opposite winds of equal speed pass through calm, not through an arbitrary direction.
  WeatherState east = a, west = a;
  east.wind_direction = {1, 0, 0};
  west.wind_direction = {-1, 0, 0};
  EXPECT_NEAR(blend(east, west, 0.5f).state.wind_speed, 0.0f, 1e-5f);
}

TEST(WeatherLibrary, AMalformedStateFailsTheLoadNamingItsFile) {
  const fs::path dir = test::fresh_temp_dir("cumulo_weather_lib");
  fs::copy_file(WeatherLibrary::default_folder() / "clear.json", dir / "clear.json");
  write_file_atomic(dir / "bad.json", "{\"coverage\": 2}");
  try {
    WeatherLibrary::load(dir);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
  EXPECT_THROW(WeatherLibrary::load(dir), Error);  // no such folder
}

}  // namespace
