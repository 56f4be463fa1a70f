// The bake pipeline: culling exactness, field accuracy, profile monotonicity, determinism, memory
// accounting, files, slices and the sample cloudscape at a reduced grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <numeric>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/bake/bake.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

using namespace cumulo::clouds::bake;
namespace cc = cumulo::clouds;

namespace {

const char* kSmallRecipe = R"({
  "name": "small", "seed": 5, "voxel_size": 16,
  "bounds": {"min": [-512, 0, -512], "max": [512, 256, 512]},
  "edits": [
    {"type": "ellipsoid", "radii": [220, 80, 160], "position": [-100, 110, 0], "detail_type": 0.8,
     "erode": {"amplitude": 24, "frequency": 0.01}},
    {"type": "metaball", "radius": 70, "position": [60, 140, 30], "blend": 40, "density_scale": 0.6},
    {"type": "capsule", "a": [-300, 0, 0], "b": [100, 0, 0], "radius": 25, "position": [0, 110, 0], "op": "subtract", "blend": 10},
    {"type": "group", "position": [250, 100, -250], "scale": [1.5, 0.6, 1], "edits": [
      {"type": "box", "size": [120, 120, 120], "rounding": 20},
      {"type": "sphere", "radius": 50, "op": "subtract"}]},
    {"type": "particles", "generate": {"count": 40, "radii": [120, 30, 120], "radius": [10, 25]},
     "position": [-250, 60, 300], "particle_blend": 12, "shear": [0.5, 0.2], "detail_type": 0.1},
    {"type": "ellipsoid", "radii": [500, 200, 500], "position": [0, 128, 0], "op": "intersect", "blend": 20}
  ]})";

Recipe small_recipe(std::optional<uint64_t> seed = {}) {
  RecipeOptions o;
  o.seed = seed;
  return parse_recipe_text(kSmallRecipe, "small.json", ".", o);
}

BakeSettings quiet() {
  BakeSettings s;
  s.show_progress = false;
  return s;
}

}  // namespace

TEST(Compose, CullingIsExactWithinTheBandAndKeepsTheSign) {
  Recipe r = small_recipe();
  BakeGrid g = make_grid(r);
  ASSERT_EQ(g.dims, glm::uvec3(64, 16, 64));
  Composed c = compose(r, g);
  // The same recipe with no culling at all: every edit's box covers everything.
  Recipe all = r;
  std::function<void(std::vector<Edit>&)> open = [&](std::vector<Edit>& es) {
    for (Edit& e : es) {
      open(e.children);
      e.parent_bounds = Aabb{glm::vec3(-1e9f), glm::vec3(1e9f)};
    }
  };
  open(all.edits);
  size_t inside = 0;
  for (uint32_t z = 0; z < g.dims.z; ++z)
    for (uint32_t y = 0; y < g.dims.y; ++y)
      for (uint32_t x = 0; x < g.dims.x; ++x) {
        size_t i = g.index(x, y, z);
        EvalSample ref = evaluate_point(all, g.position(x, y, z));
        ASSERT_EQ(c.sdf[i] < 0.0f, ref.d < 0.0f) << x << "," << y << "," << z;
        if (std::abs(ref.d) < 2.0f * 16.0f) {
          EXPECT_NEAR(c.sdf[i], ref.d, 1e-3f);
          if (ref.d < 0.0f) {
            EXPECT_NEAR(c.detail_type[i], ref.detail_type, 1e-4f);
            EXPECT_NEAR(c.density_scale[i], ref.density_scale, 1e-4f);
          }
        }
        inside += c.sdf[i] < 0.0f;
      }
  EXPECT_GT(inside, 1000u);
  EXPECT_LT(c.edit_evaluations, uint64_t(g.count()) * 6 / 2);  // culling skipped most pairs
}

TEST(Field, SphereFieldMatchesTheAnalyticDistance) {
  Recipe r = parse_recipe_text(R"({"voxel_size": 8, "bounds": {"min": [-256, -256, -256], "max": [256, 256, 256]},
    "edits": [{"type": "sphere", "radius": 100, "position": [3, -2, 5]}]})", "s.json", ".");
  BakeResult b = bake_recipe(r, quiet());
  const BakeGrid& g = b.grid;
  double worst = 0.0;
  for (size_t z = 0; z < g.dims.z; ++z)
    for (size_t y = 0; y < g.dims.y; ++y)
      for (size_t x = 0; x < g.dims.x; ++x) {
        float want = glm::length(g.position(x, y, z) - glm::vec3(3, -2, 5)) - 100.0f;
        if (want < -256.0f || want > 200.0f) continue;
        worst = std::max(worst, double(std::abs(b.field[g.index(x, y, z)] - want)));
      }
  EXPECT_LT(worst, 0.75 * 8.0);
  EXPECT_GT(b.field_stats.surface_voxels, 1000u);
}

TEST(Field, DimensionalProfileIsMonotonicWithDepth) {
  BakeResult b = bake_recipe(small_recipe(), quiet());
  const size_t n = b.grid.count();
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t c) { return b.field[a] < b.field[c]; });
  for (size_t k = 1; k < n; ++k) ASSERT_LE(b.modeling[3 * order[k]], b.modeling[3 * order[k - 1]]);
  // Zero outside, rising inside, reaching 1 at the recipe's depth.
  for (size_t i = 0; i < n; ++i) {
    if (b.field[i] >= 0.0f) {
      ASSERT_EQ(b.modeling[3 * i], 0.0f);
    }
    if (b.field[i] < 0.0f) {
      ASSERT_GT(b.modeling[3 * i], 0.0f);
    }
    if (b.field[i] <= -96.0f) {
      ASSERT_EQ(b.modeling[3 * i], 1.0f);
    }
  }
}

TEST(Bake, SameRecipeAndSeedGiveTheSameBytes) {
  std::filesystem::path root = cumulo::test::unique_temp_path("cumulo_bake_determinism");
  std::filesystem::remove_all(root);
  auto run = [&](const char* sub, std::optional<uint64_t> seed) {
    Recipe r = small_recipe(seed);
    write_bake_outputs(r, bake_recipe(r, quiet()), root / sub);
  };
  run("a", {});
  run("b", {});
  run("c", 1234);
  for (const char* f : {"modeling.nvdf", "modeling_bc1.nvdf", "field.nvdf", "field_bc1.nvdf"}) {
    auto a = cumulo::read_file_bytes(root / "a" / f), b = cumulo::read_file_bytes(root / "b" / f);
    EXPECT_EQ(a, b) << f;
    EXPECT_NE(a, cumulo::read_file_bytes(root / "c" / f)) << f << " should depend on the seed";
  }
  std::filesystem::remove_all(root);
}

TEST(Bake, FilesLoadBackWithTheirChannelsAndPlacement) {
  std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_files");
  std::filesystem::remove_all(dir);
  Recipe r = small_recipe();
  BakeResult b = bake_recipe(r, quiet());
  std::string report = write_bake_outputs(r, b, dir);
  EXPECT_NE(report.find("\"violations\": 0"), std::string::npos);
  cc::Volume m = cc::load_volume(dir / "modeling.nvdf");
  cc::check_modeling_volume(m, "modeling");
  cc::Volume f = cc::load_volume(dir / "field.nvdf");
  cc::check_field_volume(f, "field");
  cc::Volume fb = cc::load_volume(dir / "field_bc1.nvdf");
  EXPECT_EQ(fb.encoding, cc::VolumeEncoding::BC1);
  EXPECT_EQ(m.size, glm::uvec3(64, 16, 64));
  EXPECT_EQ(f.bounds_min, glm::vec3(-512, 0, -512));
  EXPECT_EQ(f.bounds_max, glm::vec3(512, 256, 512));
  // The R16 texel decodes to the field rounded down.
  for (size_t i : {size_t(0), b.grid.index(20, 7, 31), b.grid.index(40, 8, 30)}) {
    uint32_t x = i % 64, y = (i / 64) % 16, z = i / (64 * 16);
    float dec = f.decoded(x, y, z, f.channel(cc::kSignedDistance, "field"));
    EXPECT_LE(dec, b.field[i] + 1e-3f);
    EXPECT_GT(dec, b.field[i] - 0.07f);
  }
  // A recipe can place the baked field again as a "volume" edit: same inside/outside.
  cumulo::write_file_atomic(dir / "again.json", std::string(R"({"voxel_size": 16, "bounds": {"min": [-512, 0, -512], "max": [512, 256, 512]},
     "edits": [{"type": "volume", "file": "field.nvdf"}]})"));
  Recipe again = load_recipe(dir / "again.json");
  BakeResult b2 = bake_recipe(again, quiet());
  size_t same = 0;
  for (size_t i = 0; i < b.grid.count(); ++i) same += (b.field[i] < 0) == (b2.field[i] < 0);
  EXPECT_GT(same, b.grid.count() * 995 / 1000);
  std::filesystem::remove_all(dir);
}

// The coverage threshold (issue 20) reaches both modeling paths: the RGBA8 modeling NVDF's alpha at full
// resolution, and coverage.nvdf (R8, half resolution per axis, listed in bake_report.json) for the BC1 path.
TEST(Bake, CoverageThresholdIsTheModelingAlphaAndAHalfResolutionR8) {
  std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_coverage");
  std::filesystem::remove_all(dir);
  Recipe r = parse_recipe_text(R"({
    "voxel_size": 8, "bounds": {"min": [-256, 0, -256], "max": [256, 256, 256]},
    "edits": [
      {"type": "sphere", "radius": 60, "position": [-120, 128, 0], "coverage": 0.6},
      {"type": "sphere", "radius": 60, "position": [120, 128, 0]},
      {"type": "group", "coverage": 0.3, "edits": [{"type": "sphere", "radius": 40, "position": [0, 128, 160]}]},
      {"type": "box", "size": [30, 30, 30], "position": [-120, 128, 0], "op": "subtract", "coverage": 0.9}
    ]})",
                               "coverage.json", ".");
  BakeResult b = bake_recipe(r, quiet());
  const std::string report = write_bake_outputs(r, b, dir);
  cc::Volume m = cc::load_volume(dir / "modeling.nvdf");
  const uint32_t a = m.channel(cc::kCoverageThreshold, "modeling");
  EXPECT_EQ(a, 3u);
  auto alpha_at = [&](glm::vec3 p) {
    const glm::uvec3 t((p - glm::vec3(-256, 0, -256)) / 8.0f);
    return m.texel(t.x, t.y, t.z, a);
  };
  // Inside the threshold-0.6 sphere (around the cutout, which carries no attributes), everywhere in it.
  for (glm::vec3 p : {glm::vec3(-120, 128, 40), glm::vec3(-160, 128, 0), glm::vec3(-120, 170, 0), glm::vec3(-120, 100, -30)})
    EXPECT_NEAR(alpha_at(p), 0.6f, 0.5f / 255.0f) << p.x << " " << p.y << " " << p.z;
  EXPECT_NEAR(alpha_at({-120, 128, 0}), 0.6f, 0.5f / 255.0f);  // the cutout's 0.9 is not carried
  EXPECT_EQ(alpha_at({120, 128, 0}), 0.0f);            // the default sphere
  EXPECT_NEAR(alpha_at({0, 128, 160}), 0.3f, 0.5f / 255.0f);  // inherited from its group
  EXPECT_EQ(alpha_at({-240, 10, -240}), 0.0f);         // air far from every edit
  EXPECT_EQ(alpha_at({0, 240, -200}), 0.0f);
  // Inside or out, each voxel's threshold follows the nearest edit within its box: compare with the profile.
  size_t inside_a = 0;
  for (uint32_t z = 0; z < 64; ++z)
    for (uint32_t y = 0; y < 32; ++y)
      for (uint32_t x = 0; x < 64; ++x) {
        const glm::vec3 p = glm::vec3(-256, 0, -256) + (glm::vec3(x, y, z) + 0.5f) * 8.0f;
        if (m.texel(x, y, z, 0) > 0.0f && glm::distance(p, glm::vec3(-120, 128, 0)) < 55.0f) {
          ++inside_a;
          EXPECT_NEAR(m.texel(x, y, z, a), 0.6f, 0.5f / 255.0f);
        }
      }
  EXPECT_GT(inside_a, 100u);

  cc::Volume c = cc::load_volume(dir / "coverage.nvdf");
  EXPECT_EQ(c.encoding, cc::VolumeEncoding::R8);
  EXPECT_EQ(c.size, glm::uvec3(32, 16, 32));
  EXPECT_EQ(c.bounds_min, m.bounds_min);
  EXPECT_EQ(c.bounds_max, m.bounds_max);
  EXPECT_EQ(c.channel(cc::kCoverageThreshold, "coverage"), 0u);
  auto half_at = [&](glm::vec3 p) {
    const glm::uvec3 t((p - glm::vec3(-256, 0, -256)) / 16.0f);
    return c.texel(t.x, t.y, t.z, 0);
  };
  EXPECT_NEAR(half_at({-150, 136, 24}), 0.6f, 1.0f / 255.0f);
  EXPECT_EQ(half_at({120, 128, 0}), 0.0f);
  EXPECT_EQ(half_at({-240, 10, -240}), 0.0f);
  // Listed with its bytes; the compressed path counts it.
  EXPECT_NE(report.find("\"file\": \"coverage.nvdf\",\n      \"format\": \"r8\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"gpu_bytes\": 16384"), std::string::npos) << report;
  // ... and the fair-weather field (R16 at half resolution: a sphere here is at the band, 0.6).
  EXPECT_NE(report.find(std::string("\"compressed_path_bytes\": ") + std::to_string(2 * 64 * 32 * 64 / 2 + 16384 + 2 * 16384)),
            std::string::npos)
      << report;
  // A recipe without thresholds bakes zeros (threshold 0: present at any coverage).
  BakeResult plain = bake_recipe(small_recipe(), quiet());
  EXPECT_TRUE(std::all_of(plain.coverage.begin(), plain.coverage.end(), [](float v) { return v == 0.0f; }));
  std::filesystem::remove_all(dir);
}

// The fair-weather field (issue 20, volume/nvdf.h field_fair.nvdf): at half resolution, the distance to the
// clouds below CLOUD_COVERAGE_BAND only, never above the true distance to them at any point (trilinear, as the
// march samples it); a cloud at or above the band is air to it. A recipe without such a cloud writes none.
TEST(Bake, FairWeatherFieldIgnoresHighThresholdCloudsAndIsConservative) {
  Recipe r = parse_recipe_text(R"({"voxel_size": 8, "bounds": {"min": [-256, 0, -256], "max": [256, 256, 256]},
    "edits": [{"type": "sphere", "radius": 60, "position": [-120, 128, 0]},
              {"type": "sphere", "radius": 70, "position": [120, 128, 0], "coverage": 0.8}]})",
                               "fair.json", ".");
  BakeResult b = bake_recipe(r, quiet());
  ASSERT_FALSE(b.field_fair16.empty());
  const glm::uvec3 hd = b.field_fair_dims;
  EXPECT_EQ(hd, (b.grid.dims + 1u) / 2u);
  auto texel = [&](glm::ivec3 p) {
    p = glm::clamp(p, glm::ivec3(0), glm::ivec3(hd) - 1);
    return unorm16_to_field(b.field_fair16[size_t(p.x) + size_t(hd.x) * (size_t(p.y) + size_t(hd.y) * size_t(p.z))]);
  };
  const glm::vec3 bmin = b.grid.bounds_min();
  auto sample = [&](glm::vec3 w) {  // trilinear, texel centres at bmin + (i + 0.5) * 16
    const glm::vec3 u = (w - bmin) / 16.0f - 0.5f;
    const glm::ivec3 i0 = glm::ivec3(glm::floor(u));
    const glm::vec3 f = u - glm::vec3(i0);
    float v = 0.0f;
    for (int k = 0; k < 8; ++k) {
      const glm::ivec3 o(k & 1, (k >> 1) & 1, k >> 2);
      const glm::vec3 wgt = glm::mix(1.0f - f, f, glm::vec3(o));
      v += wgt.x * wgt.y * wgt.z * texel(i0 + o);
    }
    return v;
  };
  int checked = 0;
  for (float x = -248; x < 248; x += 7.3f)
    for (float y = 4; y < 252; y += 9.1f)
      for (float z = -248; z < 248; z += 11.7f) {
        const glm::vec3 w(x, y, z);
        const float truth = glm::length(w - glm::vec3(-120, 128, 0)) - 60.0f;  // the low-threshold sphere only
        ASSERT_LE(sample(w), truth + 1e-3f) << "at " << x << ", " << y << ", " << z;
        ++checked;
      }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(sample({120, 128, 0}), 100.0f) << "the high-threshold sphere's centre is air to the fair-weather field";
  EXPECT_LT(sample({-120, 128, 0}), 0.0f) << "the low-threshold sphere's centre is inside";
  const std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_fair");
  write_bake_outputs(r, b, dir);
  cc::Volume v = cc::load_volume(dir / "field_fair.nvdf");
  EXPECT_EQ(v.size, hd);
  EXPECT_EQ(v.encoding, cc::VolumeEncoding::R16);
  EXPECT_EQ(v.bounds_max, b.grid.bounds_max());
  std::filesystem::remove_all(dir);
  // Every cloud below the band: no fair-weather field (the march uses the field).
  EXPECT_TRUE(bake_recipe(small_recipe(), quiet()).field_fair16.empty());
}

TEST(Bake, MemoryAccountingMatchesTheTalkAndTheBudget) {
  const glm::uvec3 talk(512, 64, 512);  // the talk's 512 x 512 x 64, Y up
  EXPECT_EQ(bake_gpu_bytes("bc1", talk), 8388608u);    // talk: field BC1 8.389 MB
  EXPECT_EQ(bake_gpu_bytes("r16", talk), 33554432u);   // talk: 33.554 MB uncompressed
  EXPECT_EQ(bake_gpu_bytes("rgba8", talk), 67108864u);
  const uint64_t ours = bake_gpu_bytes("bc1", talk) * 2;  // modeling BC1 + field BC1
  EXPECT_EQ(ours, 16777216u);
  EXPECT_LE(ours, 25200000u);
  EXPECT_EQ(bake_gpu_bytes("bc1", talk) + talk.x * talk.y * talk.z, 25165824u);  // the talk's 25.166 MB
  // Partial blocks round up.
  EXPECT_EQ(bake_gpu_bytes("bc1", {5, 5, 2}), 2u * 2 * 2 * 8);
}

TEST(Bake, DimsOverrideResamplesTheSameBounds) {
  BakeSettings s = quiet();
  s.dims = {32, 8, 32};
  BakeResult b = bake_recipe(small_recipe(), s);
  EXPECT_EQ(b.grid.dims, glm::uvec3(32, 8, 32));
  EXPECT_EQ(b.grid.spacing, glm::vec3(32.0f));
  EXPECT_EQ(b.field_bc1_report.violations, 0u);
}

TEST(Slices, WritesPngCrossSections) {
  std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_slices");
  std::filesystem::remove_all(dir);
  Recipe r = small_recipe();
  auto files = write_slices(r, bake_recipe(r, quiet()), dir);
  EXPECT_EQ(files.size(), (3u + 2u) * 3u);  // 3 default heights + 2 vertical, 3 images each
  for (auto& f : files) {
    auto bytes = cumulo::read_file_bytes(f);
    ASSERT_GT(bytes.size(), 64u);
    EXPECT_EQ(bytes[1], 'P');
    EXPECT_EQ(bytes[2], 'N');
  }
  std::filesystem::remove_all(dir);
}

TEST(SampleCloudscape, HasTheAuthoredFeatures) {
  Recipe r = load_recipe(cumulo::repo_root() / "content/levels/sample/cloudscape.json");
  // The box the level documents (content/README.md): 4096 m square, base 600 m, top 1112 m, 8 m voxels.
  EXPECT_EQ(r.bounds_min, glm::vec3(-2048, 600, -2048));
  EXPECT_EQ(r.bounds_max, glm::vec3(2048, 1112, 2048));
  EXPECT_EQ(make_grid(r).dims, glm::uvec3(512, 64, 512));
  auto inside = [&](glm::vec3 p) { return evaluate_point(r, p).d < 0.0f; };
  EXPECT_TRUE(inside({-650, 840, -850})) << "hero cumulus core";
  EXPECT_FALSE(inside({-300, 900, 400})) << "the immersed camera sits in clear air inside the layer";
  EXPECT_FALSE(inside({1000, 840, -700})) << "the storm cloud is its own asset (storm_cloud.json)";
  // Tunnel cloud: the main tunnel runs along the immersed camera's view through the cloud body.
  EXPECT_FALSE(inside({-1011, 890, -100})) << "main tunnel";
  EXPECT_TRUE(inside({-1011, 955, -100})) << "tunnel ceiling";
  EXPECT_FALSE(inside({-900, 900, 0})) << "central cave";
}

TEST(SampleStormCloud, HasTheAuthoredFeatures) {
  Recipe r = load_recipe(cumulo::repo_root() / "content/levels/sample/storm_cloud.json");
  const glm::uvec3 dims = make_grid(r).dims;
  EXPECT_EQ(dims, glm::uvec3(180, 162, 160));  // the grown cumulonimbus and its anvil rise to 1896 m
  auto inside = [&](glm::vec3 p) { return evaluate_point(r, p).d < 0.0f; };
  // Base (1000, 620, -700), egg (45 x 60 x 45 m) at y = 840 inside a hollow chamber.
  EXPECT_TRUE(inside({1000, 840, -700})) << "egg";
  EXPECT_FALSE(inside({1080, 845, -700})) << "chamber around the egg";
  EXPECT_TRUE(inside({1100, 700, -700})) << "plume wall";
  for (float y = 606; y < 776; y += 8) EXPECT_FALSE(inside({1000, y, -700})) << "lightning hole under the egg at y " << y;
  EXPECT_FALSE(inside({1075, 1020, -650})) << "opening to the sky";
  EXPECT_TRUE(inside({1000, 1000, -580})) << "crown";
  for (float a = 0.0f; a < 6.28f; a += 0.785f)
    for (float r_m = 150.0f; r_m <= 230.0f; r_m += 20.0f) {
      const glm::vec3 wall(1000.0f + r_m * std::cos(a), 845.0f, -700.0f + r_m * std::sin(a));
      EXPECT_TRUE(inside(wall)) << "plume wall around the chamber (135 m), at least 95 m thick, at " << wall.x << ", " << wall.z;
    }
  EXPECT_FALSE(inside({1090, 860, -700})) << "the level's lair camera stands in the chamber";
  // Everything the group makes lies inside the asset's box (nothing cut off at its faces).
  BakeResult b = bake_recipe(r, quiet());
  EXPECT_GT(b.field_stats.inside_voxels, 20000u);
  int cut = 0;
  for (uint32_t y = 0; y < dims.y; ++y) {
    for (uint32_t k = 0; k < dims.z; ++k)
      for (uint32_t side : {0u, dims.x - 1})
        cut += evaluate_point(r, r.bounds_min + (glm::vec3(side, y, k) + 0.5f) * 8.0f).d < 0.0f;
    for (uint32_t i = 0; i < dims.x; ++i)
      for (uint32_t side : {0u, dims.z - 1})
        cut += evaluate_point(r, r.bounds_min + (glm::vec3(i, y, side) + 0.5f) * 8.0f).d < 0.0f;
  }
  EXPECT_EQ(cut, 0) << "voxels inside cloud on the box's side faces";
}

TEST(SampleCloudscape, ReducedBakeIsConservative) {
  Recipe r = load_recipe(cumulo::repo_root() / "content/levels/sample/cloudscape.json");
  BakeSettings s = quiet();
  s.dims = {128, 32, 128};  // 32 x 16 x 32 m voxels
  BakeResult b = bake_recipe(r, s);
  EXPECT_GT(b.field_stats.inside_voxels, 5000u);
  EXPECT_EQ(b.field_bc1_report.violations, 0u);
  EXPECT_EQ(b.field_bc1_report.midpoint_violations, 0u);
  EXPECT_EQ(b.field_bc1_report.texels, b.grid.count());
  EXPECT_LT(b.field_bc1_report.mean_error_m, 16.0);
}

TEST(Bake, GridOverTheMemoryBudgetIsRefusedNamingTheOption) {
  Recipe r = small_recipe();
  BakeSettings s = quiet();
  s.dims = {4096, 4096, 4096};  // each axis within its limit, the total (6.9e10 voxels) not
  try {
    bake_recipe(r, s);
    FAIL() << "a 4096^3 bake was accepted";
  } catch (const cumulo::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("small.json: a bake grid of 4096x4096x4096 voxels (--dims)"), std::string::npos) << m;
    EXPECT_NE(m.find("memory budget"), std::string::npos) << m;
  }
  s.dims = {};
  s.voxel_size = 0.25f;  // 4096 x 1024 x 4096 over the small recipe's box
  try {
    bake_recipe(r, s);
    FAIL() << "a 0.25 m bake of a 1 km box was accepted";
  } catch (const cumulo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("(--voxel-size 0.25)"), std::string::npos) << e.what();
  }
}

TEST(Bake, FailedWriteLeavesThePreviousOutputsUntouched) {
  std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_file_set");
  std::filesystem::remove_all(dir);
  Recipe r = small_recipe();
  write_bake_outputs(r, bake_recipe(r, quiet()), dir);
  const char* files[] = {"modeling.nvdf", "modeling_bc1.nvdf", "field.nvdf", "field_bc1.nvdf"};
  std::vector<std::vector<uint8_t>> before;
  for (const char* f : files) before.push_back(cumulo::read_file_bytes(dir / f));
  // The last file of the set cannot be written: its path is a folder now.
  std::filesystem::remove(dir / "bake_report.json");
  std::filesystem::create_directories(dir / "bake_report.json");
  Recipe other = small_recipe(99);  // different bytes
  EXPECT_THROW(write_bake_outputs(other, bake_recipe(other, quiet()), dir), cumulo::Error);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(cumulo::read_file_bytes(dir / files[i]), before[i]) << files[i];
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_NE(e.path().extension(), ".tmp") << e.path() << " left behind";
  std::filesystem::remove_all(dir);
}
