// The OrographicClouds component: its JSON (every key, defaults, errors naming the place), its painted maps (errors
// naming the file) and its agreement with the shipped level schema.
#include "modules/clouds/envelope/orographic_clouds.h"

#include <gtest/gtest.h>

#include <functional>
#include <set>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/png.h"
#include "tests/modules/clouds/envelope/grey_png16.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;
using namespace cumulo::clouds::envelope;

namespace {

const char* kFull = R"({
  "extent": {"min": [-1200, -600], "max": [1200, 1600]},
  "resolution": 128, "density": 2, "coverage": 0.75, "edge_m": 50,
  "wind": {"direction": [1, 0, 0.5], "speed": 4},
  "rules": [
    {"type": "cap", "center": "peak", "radius_m": 350, "base_m": 180, "top_m": 520, "coverage": 1, "detail_type": 0.8},
    {"type": "cap", "center": [10, 20], "radius_m": 100, "base_m": 0, "top_m": 50},
    {"type": "bank", "wind_from": [-1, 0, -0.3], "terrain_m": [20, 260], "base_above_terrain_m": 40, "thickness_m": 220,
     "coverage": 0.9, "detail_type": 0.4, "region": {"center": [-29, 267], "radius_m": 900}},
    {"type": "layer", "top_m": 60, "base_above_terrain_m": 5, "below_terrain_m": 80, "coverage": 0.7, "detail_type": 0.2,
     "region": {"center": [0, 0], "radius_m": 500}}
  ],
  "maps": {"bottom": "b.png", "top": "t.png", "coverage": "c.png", "detail": "d.png", "height_range": [0, 800],
           "relative_to": "terrain"}
})";

OrographicClouds parse(const std::string& text) {
  JsonDocument doc = parse_json_text(text, "level.json");
  return orographic_clouds_from_json(doc.view());
}

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A component with one rule (JSON text).
std::string with_rule(const std::string& rule) {
  return R"({"extent": {"min": [0, 0], "max": [100, 100]}, "rules": [)" + rule + "]}";
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST(OrographicClouds, ParsesEveryKeyAndRoundTrips) {
  const OrographicClouds c = parse(kFull);
  EXPECT_EQ(c.extent_min, glm::vec2(-1200, -600));
  EXPECT_EQ(c.extent_max, glm::vec2(1200, 1600));
  EXPECT_EQ(c.resolution, 128u);
  EXPECT_FLOAT_EQ(c.density, 2.0f);
  EXPECT_FLOAT_EQ(c.coverage, 0.75f);
  EXPECT_FLOAT_EQ(c.edge_m, 50.0f);
  EXPECT_FLOAT_EQ(c.wind_direction.z, 0.5f);
  EXPECT_FLOAT_EQ(c.wind_speed, 4.0f);
  EXPECT_EQ(c.where, "level.json: $");
  ASSERT_EQ(c.rules.size(), 4u);
  const auto& cap = std::get<CapRule>(c.rules[0].kind);
  EXPECT_TRUE(cap.at_peak);
  EXPECT_FLOAT_EQ(cap.top_m, 520.0f);
  EXPECT_FLOAT_EQ(c.rules[0].detail_type, 0.8f);
  EXPECT_EQ(c.rules[0].where, "level.json: $.rules[0]");
  EXPECT_FALSE(std::get<CapRule>(c.rules[1].kind).at_peak);
  EXPECT_EQ(std::get<CapRule>(c.rules[1].kind).center, glm::vec2(10, 20));
  EXPECT_FLOAT_EQ(c.rules[1].detail_type, 0.5f);
  const auto& bank = std::get<BankRule>(c.rules[2].kind);
  EXPECT_EQ(bank.terrain_m, glm::vec2(20, 260));
  EXPECT_FLOAT_EQ(bank.thickness_m, 220.0f);
  ASSERT_TRUE(c.rules[2].region);
  EXPECT_FLOAT_EQ(c.rules[2].region->radius_m, 900.0f);
  const auto& layer = std::get<LayerRule>(c.rules[3].kind);
  EXPECT_FLOAT_EQ(layer.below_terrain_m, 80.0f);
  EXPECT_FLOAT_EQ(layer.base_above_terrain_m, 5.0f);
  ASSERT_TRUE(c.maps);
  EXPECT_EQ(c.maps->coverage.path, "c.png");
  EXPECT_EQ(c.maps->top.where, "level.json: $.maps.top");
  EXPECT_TRUE(c.maps->relative_to_terrain);

  const Json once = orographic_clouds_to_json(c);
  const OrographicClouds again = parse(once.dump());
  EXPECT_EQ(orographic_clouds_to_json(again), once);
  EXPECT_EQ(again.rules.size(), 4u);
  EXPECT_TRUE(std::get<CapRule>(again.rules[0].kind).at_peak);
}

TEST(OrographicClouds, DefaultsAndTheRegistry) {
  const OrographicClouds c = parse(with_rule(R"({"type": "layer", "top_m": 40})"));
  EXPECT_EQ(c.resolution, 256u);
  EXPECT_FLOAT_EQ(c.density, 1.0f);
  EXPECT_FLOAT_EQ(c.coverage, 1.0f);
  EXPECT_FLOAT_EQ(c.edge_m, 35.0f);
  EXPECT_FALSE(c.maps);
  const auto& layer = std::get<LayerRule>(c.rules[0].kind);
  EXPECT_FLOAT_EQ(layer.below_terrain_m, 40.0f);  // defaults to the top
  EXPECT_FLOAT_EQ(c.rules[0].coverage, 1.0f);
  EXPECT_FALSE(c.rules[0].region);

  ecs::ComponentRegistry registry;
  register_orographic_clouds_component(registry);
  ASSERT_NE(registry.find("OrographicClouds"), nullptr);
  JsonDocument doc = parse_json_text(R"({"rules": []})", "level.json");
  EXPECT_TRUE(has(error_of([&] { registry.find("OrographicClouds")->parse(doc.view()); }), "extent"));
}

TEST(OrographicClouds, BadJsonNamesThePlace) {
  auto err = [](const std::string& text) { return error_of([&] { parse(text); }); };
  const std::string unknown = err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "colour": 1})");
  EXPECT_TRUE(has(unknown, "level.json: $.colour")) << unknown;
  EXPECT_TRUE(has(unknown, "unknown key \"colour\"")) << unknown;
  const std::string rule_key =
      err(with_rule(R"({"type": "cap", "center": "peak", "radius_m": 5, "base_m": 0, "top_m": 50, "region": {}})"));
  EXPECT_TRUE(has(rule_key, "$.rules[0].region")) << rule_key;  // a cap has its own radius
  const std::string top =
      err(with_rule(R"({"type": "cap", "center": [0, 0], "radius_m": 5, "base_m": 300, "top_m": 300})"));
  EXPECT_TRUE(has(top, "$.rules[0].top_m")) << top;
  EXPECT_TRUE(has(top, "must be at least 10 m above base_m")) << top;
  const std::string thin =
      err(with_rule(R"({"type": "cap", "center": [0, 0], "radius_m": 5, "base_m": 300, "top_m": 305})"));
  EXPECT_TRUE(has(thin, "$.rules[0].top_m")) << thin;
  const std::string bank =
      err(with_rule(R"({"type": "bank", "wind_from": [1, 0, 0], "terrain_m": [0, 10], "thickness_m": 0})"));
  EXPECT_TRUE(has(bank, "$.rules[0].thickness_m")) << bank;
  const std::string layer = err(with_rule(R"({"type": "layer", "top_m": 20, "base_above_terrain_m": 30})"));
  EXPECT_TRUE(has(layer, "$.rules[0].top_m")) << layer;
  const std::string radius =
      err(with_rule(R"({"type": "cap", "center": [0, 0], "radius_m": 0, "base_m": 0, "top_m": 50})"));
  EXPECT_TRUE(has(radius, "$.rules[0].radius_m")) << radius;
  const std::string region = err(with_rule(
      R"({"type": "bank", "wind_from": [1, 0, 0], "terrain_m": [0, 10], "thickness_m": 50, "region": {"center": [0, 0], "radius_m": -3}})"));
  EXPECT_TRUE(has(region, "$.rules[0].region.radius_m")) << region;
  const std::string range =
      err(with_rule(R"({"type": "bank", "wind_from": [1, 0, 0], "terrain_m": [50, 10], "thickness_m": 50})"));
  EXPECT_TRUE(has(range, "$.rules[0].terrain_m")) << range;
  const std::string wind =
      err(with_rule(R"({"type": "bank", "wind_from": [0, 1, 0], "terrain_m": [0, 10], "thickness_m": 50})"));
  EXPECT_TRUE(has(wind, "$.rules[0].wind_from")) << wind;
  const std::string type = err(with_rule(R"({"type": "fog", "top_m": 5})"));
  EXPECT_TRUE(has(type, "$.rules[0].type")) << type;
  const std::string peak =
      err(with_rule(R"({"type": "cap", "center": "summit", "radius_m": 5, "base_m": 0, "top_m": 50})"));
  EXPECT_TRUE(has(peak, "$.rules[0].center")) << peak;
  const std::string extent = err(R"({"extent": {"min": [0, 0], "max": [100, -5]}})");
  EXPECT_TRUE(has(extent, "$.extent")) << extent;
  EXPECT_TRUE(has(extent, "max > min")) << extent;
  EXPECT_TRUE(has(err(R"({"extent": {"min": [0, 0]}})"), "$.extent"));
  EXPECT_TRUE(has(err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "resolution": 8})"), "$.resolution"));
  EXPECT_TRUE(has(err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "coverage": 1.5})"), "$.coverage"));
  EXPECT_TRUE(has(err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "edge_m": 0})"), "$.edge_m"));
  EXPECT_TRUE(
      has(err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "maps": {"bottom": "b.png", "height_range": [0, 1]}})"),
          "$.maps"));
  EXPECT_TRUE(has(
      err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "maps": {"bottom": "b.png", "top": "t.png", "height_range": [5, 1]}})"),
      "$.maps.height_range"));
  EXPECT_TRUE(has(
      err(R"({"extent": {"min": [0, 0], "max": [1, 1]}, "maps": {"bottom": "b.png", "top": "t.png", "height_range": [0, 1], "relative_to": "ground"}})"),
      "$.maps.relative_to"));
}

TEST(OrographicClouds, PaintedMapErrorsNameTheFileAndThePlace) {
  test::TempDir tmp(test::test_temp_name("cumulo_orographic"));
  const std::vector<uint8_t> grey8(16 * 16, 128);
  write_png(tmp.path / "b.png", grey8.data(), 16, 16, 1);
  test::write_grey_png16(tmp.path / "t.png", std::vector<uint16_t>(16 * 16, 40000), 16, 16);
  write_png(tmp.path / "small.png", grey8.data(), 8, 8, 1);
  write_file_atomic(tmp.path / "text.png", std::string("not a picture"));
  auto spec = [](const std::string& top) {
    return parse(R"({"extent": {"min": [0, 0], "max": [100, 100]}, "maps": {"bottom": "b.png", "top": ")" + top +
                 R"(", "height_range": [0, 800]}})");
  };

  OrographicClouds ok = spec("t.png");
  resolve_orographic_clouds(ok, tmp.path);
  ASSERT_TRUE(ok.painted);
  EXPECT_EQ(ok.level_dir, tmp.path);
  EXPECT_EQ(ok.painted->bottom.width, 16u);
  EXPECT_NEAR(ok.painted->bottom.values[0], 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(ok.painted->top.values[5], 40000.0f / 65535.0f, 1e-6f);  // 16 bits kept

  for (const char* bad : {"missing.png", "text.png", "small.png"}) {
    OrographicClouds c = spec(bad);
    const std::string e = error_of([&] { resolve_orographic_clouds(c, tmp.path); });
    EXPECT_TRUE(has(e, "level.json: $.maps.top")) << e;
    EXPECT_TRUE(has(e, bad)) << e;
  }
  OrographicClouds small = spec("small.png");
  const std::string mismatch = error_of([&] { resolve_orographic_clouds(small, tmp.path); });
  EXPECT_TRUE(has(mismatch, "8x8")) << mismatch;
  EXPECT_TRUE(has(mismatch, "16x16")) << mismatch;
  OrographicClouds text = spec("text.png");
  EXPECT_TRUE(has(error_of([&] { resolve_orographic_clouds(text, tmp.path); }), "not a readable PNG"));
}

// Every key the writer gives (all of them, for a full component) is a property of the shipped schema's definition,
// and every property there is one the parser reads: the two cannot drift apart.
TEST(OrographicClouds, AgreesWithTheLevelSchema) {
  const Json schema = Json::parse(read_file_text(repo_root() / "content/schemas/level.schema.json"));
  const Json& defs = schema["$defs"];
  ASSERT_EQ(defs["entity"]["properties"]["components"]["properties"]["OrographicClouds"]["$ref"],
            "#/$defs/OrographicClouds");
  auto def = [&](const Json& ref) { return defs[ref["$ref"].get<std::string>().substr(8)]; };
  auto same_keys = [](const Json& props, const Json& value, const std::string& at) {
    std::set<std::string> a, b;
    for (const auto& [k, v] : props.items()) a.insert(k);
    for (const auto& [k, v] : value.items()) b.insert(k);
    EXPECT_EQ(a, b) << at;
  };
  const Json full = orographic_clouds_to_json(parse(kFull));
  const Json& top = defs["OrographicClouds"];
  same_keys(top["properties"], full, "OrographicClouds");
  same_keys(top["properties"]["extent"]["properties"], full["extent"], "extent");
  same_keys(top["properties"]["wind"]["properties"], full["wind"], "wind");
  same_keys(def(top["properties"]["maps"])["properties"], full["maps"], "maps");
  std::set<std::string> types;
  for (const Json& rule : full["rules"]) {
    const std::string type = rule["type"];
    for (const Json& option : defs["OrographicRule"]["oneOf"]) {
      const Json d = def(option);
      if (d["properties"]["type"]["const"] != type) continue;
      types.insert(type);
      same_keys(d["properties"], rule, "rule " + type);  // kFull's bank and layer have a region
      if (rule.contains("region")) same_keys(def(d["properties"]["region"])["properties"], rule["region"], "region");
    }
  }
  EXPECT_EQ(types, (std::set<std::string>{"cap", "bank", "layer"}));
  for (const char* name : {"OrographicCap", "OrographicBank", "OrographicLayer"})
    for (const Json& r : defs[name]["required"])
      EXPECT_TRUE(defs[name]["properties"].contains(r.get<std::string>())) << name;
}
