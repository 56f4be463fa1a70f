// The cloud-formation simulation (`cumulo grow`): water conservation, determinism across thread counts,
// the atmosphere's control of the shape (an inversion caps and spreads, none lets a thermal tower, a
// cumulonimbus spreads under its tropopause), the attributes from the simulation, errors and the cache,
// and the committed sample clouds regrowing byte for byte. Small grids: each grow is a second or two.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/parallel.h"
#include "modules/clouds/bake/bake.h"
#include "modules/clouds/bake/grow/grow_cache.h"
#include "modules/clouds/bake/grow/grown_attributes.h"
#include "modules/clouds/bake/grow/grown_cloud.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo::clouds;
using namespace cumulo::clouds::grow;

namespace {

// A small mediocris: 32 x 24 x 32 cells of 24 m (144 m physical).
const char* kSmall = R"({"preset": "mediocris", "seed": 4, "grid": {"cells": [32, 24, 32], "cell": 24},
  "time": {"steps": 150, "dt": 12},
  "thermals": [{"position": [0, 0], "radius": 220, "heat": 2.5, "moisture": 3.0, "seed": 1}]})";

GrowSpec spec_of(const std::string& text, const std::string& name = "small.json") { return parse_grow_spec_text(text, name); }

GrownCloud run_grow(const GrowSpec& s, GrowReport* r = nullptr) { return grow_cloud(s, r, nullptr); }

// Cells above the iso per level of the grown cloud.
std::vector<int> area_per_level(const GrownCloud& g) {
  std::vector<int> a(g.dims.y, 0);
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) a[j] += g.cloud_water[g.index(i, j, k)] > g.iso;
  return a;
}

struct ScopedThreads {
  explicit ScopedThreads(int n) { setenv("CUMULO_THREADS", std::to_string(n).c_str(), 1); }
  ~ScopedThreads() { unsetenv("CUMULO_THREADS"); }
};

}  // namespace

// Condensation and evaporation move water between vapour and cloud water and never make or lose any:
// over the whole grid the sum changes only by float rounding.
TEST(Grow, PhaseChangeConservesWater) {
  GrowSpec s = spec_of(kSmall);
  CloudSolver solver(s.solver);
  for (int i = 0; i < 90; ++i) solver.step();
  const WaterBudget before = solver.budget();
  ASSERT_GT(before.final_cloud_water, 0.0) << "the test needs cloud water to condense and evaporate";
  solver.phase_change();
  const WaterBudget after = solver.budget();
  EXPECT_NEAR(after.final_total, before.final_total, 1e-6 * before.final_total);
}

// The whole run: the water sources add and the MacCormack advection (not conservative) may drift. The
// stated tolerance: the drift stays under 2 % of the grid's water, and the report accounts for it.
TEST(Grow, WaterBudgetIsAccountedWithinTolerance) {
  GrowReport r;
  run_grow(spec_of(kSmall), &r);
  EXPECT_GT(r.water.sourced, 0.0);
  EXPECT_NEAR(r.water.final_total, r.water.initial + r.water.sourced - r.water.dried + r.water.advection_residual,
              1e-9 * r.water.initial);
  EXPECT_LT(std::abs(r.total_water_drift), 0.02) << "advection made or lost " << 100 * r.total_water_drift << " % of the water";
}

TEST(Grow, SameSeedGivesTheSameBytesWhateverTheThreadCount) {
  const GrowSpec s = spec_of(kSmall);
  std::vector<uint8_t> one, two;
  {
    ScopedThreads t(1);
    one = serialize_volume(grown_to_volume(run_grow(s)));
  }
  {
    ScopedThreads t(2);
    two = serialize_volume(grown_to_volume(run_grow(s)));
  }
  EXPECT_EQ(one, two);
  GrowSpec other = spec_of(R"({"preset": "mediocris", "seed": 5, "grid": {"cells": [32, 24, 32], "cell": 24},
    "time": {"steps": 150, "dt": 12}, "thermals": [{"position": [0, 0], "radius": 220, "heat": 2.5, "moisture": 3.0, "seed": 1}]})");
  EXPECT_NE(serialize_volume(grown_to_volume(run_grow(other))), one) << "the seed changes the plume roots";
  EXPECT_NE(other.key, s.key);
}

// The same thermal under a strong low inversion spreads flat; without one it towers.
TEST(Grow, AnInversionSpreadsTheCloudFlatWithoutOneItTowers) {
  const std::string common = R"("grid": {"cells": [40, 28, 40], "cell": 20}, "time": {"steps": 170, "dt": 12},
    "thermals": [{"position": [0, 0], "radius": 200, "heat": 2.5, "moisture": 3.0, "seed": 1}])";
  GrowReport capped, free;
  run_grow(spec_of(R"({"preset": "mediocris", "atmosphere": {"inversion": {"height": 150, "thickness": 20, "strength": 8}}, )" + common + "}"),
       &capped);
  run_grow(spec_of(R"({"preset": "mediocris", "atmosphere": {"lapse_rate": 7.5, "upper_lapse_rate": 7.5, "humidity_above": 0.6,
       "inversion": {"height": 100000, "strength": 0}}, )" + common + "}"),
       &free);
  const float capped_height = capped.cloud_top_m - capped.cloud_base_m, free_height = free.cloud_top_m - free.cloud_base_m;
  EXPECT_LT(capped.cloud_top_m, 150.0f + 3 * 20.0f) << "the inversion (150 m) caps the cloud";
  EXPECT_GT(free.cloud_top_m, capped.cloud_top_m + 120.0f) << "without an inversion the thermal rises further";
  const float capped_aspect = std::max(capped.cloud_size.x, capped.cloud_size.z) / capped_height;
  const float free_aspect = std::max(free.cloud_size.x, free.cloud_size.z) / free_height;
  EXPECT_GT(capped_aspect, 2.0f);
  EXPECT_GT(capped_aspect, 1.5f * free_aspect) << "capped: wide and flat; free: a tower";
}

// A cumulonimbus rises to its tropopause and spreads there into an anvil wider than its trunk.
TEST(Grow, ACumulonimbusReachesItsCeilingAndSpreads) {
  GrowReport r;
  const GrowSpec s = spec_of(R"({"preset": "cumulonimbus", "grid": {"cells": [40, 32, 40], "cell": 40}, "time": {"steps": 200, "dt": 14},
    "atmosphere": {"tropopause": 1000}, "thermals": [{"position": [0, 0], "radius": 360, "heat": 3.5, "moisture": 5.0, "seed": 1}]})");
  const GrownCloud g = run_grow(s, &r);
  EXPECT_GT(r.cloud_top_m, 0.85f * 1000.0f) << "the updraft reaches the tropopause";
  const std::vector<int> area = area_per_level(g);
  int top = 0, widest_top = 0;
  for (int j = 0; j < int(area.size()); ++j)
    if (area[j] > 0) top = j;
  int base = 0;
  while (base < int(area.size()) && area[base] == 0) ++base;
  for (int j = std::max(base, top - 4); j <= top; ++j) widest_top = std::max(widest_top, area[j]);
  const int trunk = area[base + (top - base) / 2];
  EXPECT_GT(widest_top, 2 * trunk) << "the anvil (top levels) is wider than the trunk at mid height";
}

// Billows where cloud water is made (updrafts, rising tops), wisps where it is lost (base, flanks): the
// top third of the baked cloud is billowier than its bottom third by at least 0.1 (detail type, 0..1).
TEST(Grow, BakedDetailTypeIsBillowierAtTheTopThanAtTheBase) {
  const auto dir = cumulo::test::unique_temp_path("cumulo_grow_bake");
  fs::create_directories(dir);
  cumulo::write_file_atomic(dir / "cloud.json", kSmall);
  setenv("CUMULO_CACHE_DIR", (dir / "cache").c_str(), 1);
  const std::string recipe = R"({"name": "g", "voxel_size": 16, "bounds": {"min": [-512, 0, -512], "max": [512, 512, 512]},
    "edits": [{"type": "grown", "spec": "cloud.json", "position": [0, 32, 0]}]})";
  const bake::Recipe r = bake::parse_recipe_text(recipe, "g.json", dir);
  bake::BakeSettings settings;
  settings.show_progress = false;
  settings.verify = false;
  const bake::BakeResult b = bake::bake_recipe(r, settings);
  unsetenv("CUMULO_CACHE_DIR");
  const auto& gr = b.grid;
  int lo = INT32_MAX, hi = -1;
  for (uint32_t z = 0; z < gr.dims.z; ++z)
    for (uint32_t y = 0; y < gr.dims.y; ++y)
      for (uint32_t x = 0; x < gr.dims.x; ++x)
        if (b.modeling[3 * gr.index(x, y, z)] > 0.0f) lo = std::min(lo, int(y)), hi = std::max(hi, int(y));
  ASSERT_GT(hi, lo + 5) << "the grown cloud is in the bake";
  double sum[3] = {0, 0, 0};
  int n[3] = {0, 0, 0};
  for (uint32_t z = 0; z < gr.dims.z; ++z)
    for (uint32_t y = 0; y < gr.dims.y; ++y)
      for (uint32_t x = 0; x < gr.dims.x; ++x) {
        const size_t i = gr.index(x, y, z);
        if (!(b.modeling[3 * i] > 0.0f)) continue;
        const int third = std::min(2, int(3 * (int(y) - lo) / (hi - lo + 1)));
        sum[third] += b.modeling[3 * i + 1], ++n[third];
      }
  ASSERT_GT(n[0], 0);
  ASSERT_GT(n[2], 0);
  const double bottom = sum[0] / n[0], top = sum[2] / n[2];
  EXPECT_GT(top, bottom + 0.1) << "top third " << top << ", bottom third " << bottom;
  std::printf("detail type: top third %.3f, bottom third %.3f\n", top, bottom);
  // The faithful form: the edit's constant detail type everywhere.
  bake::RecipeOptions faithful;
  faithful.grown_constant = true;
  setenv("CUMULO_CACHE_DIR", (dir / "cache").c_str(), 1);
  const bake::Recipe rc = bake::parse_recipe_text(recipe, "g.json", dir, faithful);
  unsetenv("CUMULO_CACHE_DIR");
  const bake::BakeResult bc = bake::bake_recipe(rc, settings);
  for (size_t i = 0; i < gr.count(); ++i)
    if (bc.modeling[3 * i] > 0.0f) ASSERT_NEAR(bc.modeling[3 * i + 1], 0.5f, 1e-6f);
  fs::remove_all(dir);
}

// A bad spec names the file and the JSON path, and grows nothing into the cache.
TEST(Grow, BadSpecGetsAClearErrorAndLeavesTheCacheUntouched) {
  auto message = [](const std::string& text) {
    try {
      spec_of(text, "bad.json");
    } catch (const cumulo::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message(R"({"preset": "cumulus"})").find("bad.json: $.preset"), std::string::npos) << message(R"({"preset": "cumulus"})");
  EXPECT_NE(message(R"({"grid": {"cells": [30, 24, 32]}})").find("$.grid.cells[0]"), std::string::npos);
  EXPECT_NE(message(R"({"thermals": []})").find("$.thermals"), std::string::npos);
  EXPECT_NE(message(R"({"atmosphere": {"humidty": [0.8, 0.5]}})").find("humidty"), std::string::npos);
  EXPECT_NE(message(R"({"time": {"dt": -1}})").find("$.time.dt"), std::string::npos);
  EXPECT_NE(message(R"({"thermals": [{"position": [100000, 0], "radius": 200, "heat": 1, "moisture": 1}]})")
                .find("$.thermals[0].position"),
            std::string::npos);
  std::string budget = "(no error)";
  try {
    run_grow(spec_of(R"({"grid": {"cells": [512, 512, 512], "cell": 12}})", "bad.json"));
  } catch (const cumulo::Error& e) {
    budget = e.what();
  }
  EXPECT_NE(budget.find("bad.json: a grow grid of 512x512x512 cells"), std::string::npos) << budget;
  EXPECT_NE(budget.find("memory budget"), std::string::npos) << budget;
  EXPECT_NE(message("{\"preset\": \"humilis\",").find("bad.json:"), std::string::npos) << "a truncated file";
  EXPECT_NE(message("{\"seed\": 1,").find("bad.json"), std::string::npos);

  const auto dir = cumulo::test::unique_temp_path("cumulo_grow_bad");
  fs::create_directories(dir);
  setenv("CUMULO_CACHE_DIR", (dir / "cache").c_str(), 1);
  cumulo::write_file_atomic(dir / "none.json", R"({"preset": "humilis", "grid": {"cells": [16, 12, 16], "cell": 16},
    "time": {"steps": 3, "dt": 10}})");
  const std::string recipe = R"({"name": "g", "voxel_size": 16, "bounds": {"min": [-256, 0, -256], "max": [256, 256, 256]},
    "edits": [{"type": "grown", "spec": "none.json"}]})";
  std::string what;
  try {
    bake::parse_recipe_text(recipe, "g.json", dir);
  } catch (const cumulo::Error& e) {
    what = e.what();
  }
  unsetenv("CUMULO_CACHE_DIR");
  EXPECT_NE(what.find("g.json: $.edits[0].spec"), std::string::npos) << what;
  EXPECT_NE(what.find("no cloud grew"), std::string::npos) << what;
  size_t entries = 0;
  if (fs::exists(dir / "cache" / "grown"))
    for (const auto& e : fs::directory_iterator(dir / "cache" / "grown"))
      if (e.path().extension() != ".lock") ++entries;
  EXPECT_EQ(entries, 0u) << "a failed grow leaves no cache entry";
  fs::remove_all(dir);
}

// Grown once into the cache, then found there by key; a changed spec is a new key.
TEST(Grow, CacheIsKeyedByTheSpecsContent) {
  const auto dir = cumulo::test::unique_temp_path("cumulo_grow_cache");
  fs::create_directories(dir);
  setenv("CUMULO_CACHE_DIR", (dir / "cache").c_str(), 1);
  cumulo::write_file_atomic(dir / "c.json", kSmall);
  const GrowSpec s = load_grow_spec(dir / "c.json");
  const ResolvedGrown first = resolve_grown(s, dir / "c.json", false);
  EXPECT_TRUE(first.grew);
  const ResolvedGrown again = resolve_grown(s, dir / "c.json", false);
  EXPECT_FALSE(again.grew);
  EXPECT_EQ(again.dir, first.dir);
  // Same content, other whitespace and member order: the same key (the merged JSON is what is hashed).
  cumulo::write_file_atomic(dir / "c.json", std::string(kSmall) + "\n\n");
  EXPECT_EQ(load_grow_spec(dir / "c.json").key, s.key);
  unsetenv("CUMULO_CACHE_DIR");
  fs::remove_all(dir);
}

// The committed sample clouds: each folder's key matches its spec (a stale commit would be regrown on
// every clean run), and the smallest regrows to the same bytes.
TEST(Grow, CommittedSampleCloudsMatchTheirSpecs) {
  const fs::path grown = fs::path(CUMULO_SOURCE_DIR) / "content/levels/sample/grown";
  ASSERT_TRUE(fs::is_directory(grown));
  fs::path smallest;
  uintmax_t smallest_cells = UINTMAX_MAX;
  for (const auto& e : fs::directory_iterator(grown)) {
    if (e.path().extension() != ".json") continue;
    const GrowSpec s = load_grow_spec(e.path());
    const fs::path dir = committed_grow_folder(e.path());
    EXPECT_EQ(recorded_grow_key(dir), grow_key_hex(s)) << e.path() << ": regrow it with `cumulo grow " << e.path().filename().string()
                                                       << " -o " << dir.filename().string() << "`";
    const uintmax_t cells = uintmax_t(s.solver.dims.x) * s.solver.dims.y * s.solver.dims.z * s.steps;
    if (cells < smallest_cells) smallest_cells = cells, smallest = e.path();
  }
  ASSERT_FALSE(smallest.empty());
  const GrowSpec s = load_grow_spec(smallest);
  const std::vector<uint8_t> regrown = serialize_volume(grown_to_volume(run_grow(s)));
  EXPECT_EQ(regrown, cumulo::read_file_bytes(committed_grow_folder(smallest) / "grown.nvdf")) << smallest;
}
