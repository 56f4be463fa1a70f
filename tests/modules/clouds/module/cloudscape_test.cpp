// The Cloudscape component's JSON and the preparation of its assets (bake cache, folders, errors).
#include "modules/clouds/scene/cloudscape.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <thread>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/scene/cloudscape_assets.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;
using namespace cumulo::clouds;

namespace {

Cloudscape parse(const std::string& text) {
  JsonDocument doc = parse_json_text(text, "level.json");
  return cloudscape_from_json(doc.view());
}

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// A private bake cache for this process.
struct CacheDir {
  fs::path dir = test::unique_temp_path("cumulo_cloudscape_cache");
  CacheDir() {
    fs::remove_all(dir);
    ::setenv("CUMULO_CACHE_DIR", dir.c_str(), 1);
  }
  ~CacheDir() {
    ::unsetenv("CUMULO_CACHE_DIR");
    fs::remove_all(dir);
  }
};

}  // namespace

TEST(Cloudscape, JsonRoundTripAndDefaults) {
  Cloudscape c = parse(R"({"asset": "sky.json", "density": 2, "wind": {"direction": [0, 0, 1], "speed": 5}, "dissipation": 0.25})");
  EXPECT_EQ(c.asset, "sky.json");
  EXPECT_FLOAT_EQ(c.density, 2.0f);
  EXPECT_FLOAT_EQ(c.wind_direction.z, 1.0f);
  EXPECT_FLOAT_EQ(c.wind_speed, 5.0f);
  EXPECT_FLOAT_EQ(c.dissipation, 0.25f);
  EXPECT_EQ(c.where, "level.json: $.asset");
  Cloudscape again = parse(cloudscape_to_json(c).dump());
  EXPECT_EQ(again.asset, c.asset);
  EXPECT_FLOAT_EQ(again.dissipation, c.dissipation);
  Cloudscape d = parse(R"({"asset": "x"})");
  EXPECT_FLOAT_EQ(d.density, 1.0f);
  EXPECT_FLOAT_EQ(d.dissipation, 0.0f);
}

TEST(Cloudscape, BadJsonNamesThePlace) {
  EXPECT_NE(error_of([] { parse(R"({"asset": ""})"); }).find("$.asset"), std::string::npos);
  EXPECT_NE(error_of([] { parse(R"({"asset": "a", "density": -1})"); }).find("$.density"), std::string::npos);
  EXPECT_NE(error_of([] { parse(R"({"asset": "a", "dissipation": 2})"); }).find("$.dissipation"), std::string::npos);
  EXPECT_NE(error_of([] { parse(R"({"asset": "a", "colour": 1})"); }).find("unknown key \"colour\""), std::string::npos);
  EXPECT_NE(error_of([] { parse(R"({"asset": "a", "wind": {"speed": "fast"}})"); }).find("$.wind.speed"), std::string::npos);
  // No asset: a grown cloud's (the clouds module refuses it at level load on an entity without a CloudGrowth).
  const Cloudscape none = parse(R"({"density": 1})");
  EXPECT_TRUE(none.asset.empty());
  EXPECT_EQ(none.where, "level.json: $");
  EXPECT_FALSE(cloudscape_to_json(none).contains("asset"));
}

TEST(Cloudscape, RecipeIsBakedOnceIntoTheCacheAndRebakedWhenItChanges) {
  CacheDir cache;
  fs::path dir = test::unique_temp_path("cumulo_cloudscape_recipe");
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::path recipe = dir / "small.json";
  fs::copy_file("tests/modules/clouds/module/data/small_cloud.json", recipe);
  fs::path baked = prepare_cloudscape_asset(recipe, "level.json: $.x");
  EXPECT_EQ(baked.parent_path(), cache.dir / "bakes");
  for (const char* f : {"modeling.nvdf", "modeling_bc1.nvdf", "field.nvdf", "field_bc1.nvdf"})
    EXPECT_TRUE(fs::is_regular_file(baked / f)) << f;
  const auto stamp = fs::last_write_time(baked / "field.nvdf");
  EXPECT_EQ(prepare_cloudscape_asset(recipe, "w"), baked);  // reused: not rewritten
  EXPECT_EQ(fs::last_write_time(baked / "field.nvdf"), stamp);
  // An edited recipe gets a new cache folder.
  std::string text = read_file_text(recipe);
  text.replace(text.find("\"radius\": 100"), 13, "\"radius\": 90");
  write_file_atomic(recipe, text);
  fs::path rebaked = prepare_cloudscape_asset(recipe, "w");
  EXPECT_NE(rebaked, baked);
  EXPECT_TRUE(fs::is_regular_file(rebaked / "field_bc1.nvdf"));
  // A baked folder can be named directly.
  EXPECT_EQ(prepare_cloudscape_asset(baked, "w"), baked);
  fs::remove_all(dir);
}

TEST(Cloudscape, BadAssetsAreRefusedNamingTheLevelPlace) {
  CacheDir cache;
  fs::path dir = test::unique_temp_path("cumulo_cloudscape_bad");
  fs::remove_all(dir);
  fs::create_directories(dir / "half");
  write_file_atomic(dir / "half" / "field.nvdf", std::string("x"));
  write_file_atomic(dir / "notes.txt", std::string("x"));
  write_file_atomic(dir / "broken.json", std::string("{\"edits\": ["));
  const std::string where = "level.json: $.entities[1].components.Cloudscape.asset";
  std::string missing = error_of([&] { prepare_cloudscape_asset(dir / "absent.json", where); });
  EXPECT_NE(missing.find(where), std::string::npos) << missing;
  EXPECT_NE(missing.find("not found"), std::string::npos) << missing;
  std::string half = error_of([&] { prepare_cloudscape_asset(dir / "half", where); });
  EXPECT_NE(half.find("modeling.nvdf"), std::string::npos) << half;
  EXPECT_NE(half.find("field_bc1.nvdf"), std::string::npos) << half;
  EXPECT_NE(error_of([&] { prepare_cloudscape_asset(dir / "notes.txt", where); }).find("neither a recipe"),
            std::string::npos);
  std::string broken = error_of([&] { prepare_cloudscape_asset(dir / "broken.json", where); });
  EXPECT_NE(broken.find(where), std::string::npos) << broken;
  EXPECT_NE(broken.find("broken.json"), std::string::npos) << broken;
  fs::remove_all(dir);
}
