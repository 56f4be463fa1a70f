// The march's inputs made on the GPU from the solver's state (grow_gpu::GpuGrownAsset, issue 26) against what they
// must be, on lavapipe with validation:
//  - RegeneratedSdfIsConservative: the field image never exceeds the exact distance of the same mask (the CPU's
//    exact EDT, volume/distance.h, with derive_modeling's iso-crossing), and is close to it on average;
//  - AttributesMatchTheOfflineDerivation: the modeling image against grown_attributes.cpp's derive_modeling of the
//    same state and the bake's encoding, voxel for voxel; the percentiles exactly;
//  - AssetUpdateIsDeterministic: the same state gives the same bytes, a later state other bytes.
// A 32x20x32 grid (24 game m cells) with a cloud grown on the CPU.
//
// DISABLED_AssetUpdateTime64x40x64 times an update for a congestus-sized grid at 8 m (run it by hand with
// --gtest_also_run_disabled_tests).
#include "modules/clouds/grow_gpu/grown_asset_gpu.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/timestamps.h"
#include "modules/clouds/bake/field.h"
#include "modules/clouds/bake/grow/grow_spec.h"
#include "modules/clouds/bake/grow/grown_attributes.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/volume.h"

using namespace cumulo;
using namespace cumulo::clouds;
using grow_gpu::Field;

namespace {

// A mediocris thermal on 32x20x32 cells of 24 game m (144 m physical), the GrowGpu tests' at twice the width: a
// cloud of ~650 cells by 960 s. The air dries from 900 s, so about half the cloud is evaporating (the density
// scale's evaporating term) and the GPU steps run every stage.
const char* kSpec = R"({"preset": "mediocris", "seed": 3, "grid": {"cells": [32, 20, 32], "cell": 24},
  "time": {"steps": 120, "dt": 12},
  "decay": {"start": 900, "rate": 0.0005, "humidity": 0.9}})";
constexpr int kWarmSteps = 80;  // CPU steps before the comparison (960 s)

// R16's step over -256..4096 m.
constexpr double kQuantum = (kSdfRangeMax - kSdfRangeMin) / 65535.0;
// The field's stated accuracy, the mean of (exact - stored): over all voxels, less the safety margin's share (1 % of
// the mean positive distance), at most kFieldMeanError; within 4 voxels of the surface, margin included, at most
// kFieldBandError. Rounding down costs half a quantum (0.033 m) on average; the 3x3x3 pass lowers a few voxels next
// to the surface where the iso-crossing and the voxel-centre distance disagree. Measured on lavapipe: over all
// voxels 0.041 m (8 m voxels), 0.038 m (6 m), 0.111 m (the sponge: every voxel is near a surface), plus the margin's
// 1.24 m; within 4 voxels 0.191 m, 0.133 m, 0.111 m.
constexpr double kFieldMeanError = 0.15;
constexpr double kFieldBandError = 0.3;

gpu::ContextDesc validated() {
  gpu::ContextDesc cd;
  cd.validation = true;
  return cd;
}

grow::GrowSpec spec() { return grow::parse_grow_spec_text(kSpec, "grown_asset_gpu_test.json"); }

struct Grown {
  grow::GrowSpec spec = ::spec();
  grow::CloudSolver cpu{spec.solver};
  Grown() {
    for (int s = 0; s < kWarmSteps; ++s) cpu.step();
  }
};

double max_abs(const std::vector<float>& v) {
  double m = 0.0;
  for (float a : v) m = std::max(m, double(std::abs(a)));
  return m;
}

// The solver's whole box as a grown cloud in the asset's frame: what derive_modeling reads (no crop, no speckle
// removal: the GPU makes neither).
grow::GrownCloud full_box(const grow::CloudSolver& cpu, const grow_gpu::GrownAssetGrid& grid, float cell, float iso) {
  grow::GrownCloud g;
  g.dims = glm::uvec3(cpu.dims());
  g.cell = cell;
  g.origin = grid.origin;
  g.iso = iso;
  g.cloud_water = cpu.cloud_water();
  g.condensation = cpu.condensation();
  g.vertical_velocity = cpu.vertical_velocity();
  g.growth = cpu.growth();
  return g;
}

// The exact signed distance of the mask `cloud water > iso` (volume/distance.h's EDT, the surface halfway between
// voxel centres), with derive_modeling's iso-crossing next to the surface, clamped to the field's range.
std::vector<float> exact_distance(const std::vector<float>& q, glm::ivec3 n, float voxel, float iso) {
  const glm::uvec3 d(n);
  const size_t count = q.size();
  std::vector<uint8_t> inside(count);
  for (size_t c = 0; c < count; ++c) inside[c] = q[c] > iso;
  std::vector<float> sdf = signed_distance_from_mask(inside, d, voxel);
  const size_t sy = d.x, sz = size_t(d.x) * d.y;
  for (uint32_t z = 1; z + 1 < d.z; ++z)
    for (uint32_t y = 1; y + 1 < d.y; ++y)
      for (uint32_t x = 1; x + 1 < d.x; ++x) {
        const size_t c = x + sy * y + sz * z;
        const bool s = inside[c];
        if (inside[c - 1] == s && inside[c + 1] == s && inside[c - sy] == s && inside[c + sy] == s &&
            inside[c - sz] == s && inside[c + sz] == s)
          continue;
        const glm::vec3 grad(q[c + 1] - q[c - 1], q[c + sy] - q[c - sy], q[c + sz] - q[c - sz]);
        const float len = glm::length(grad) / (2.0f * voxel);
        if (len <= 0.0f) continue;
        const float e = (iso - q[c]) / len;
        if (std::abs(e) < std::abs(sdf[c]) && (e > 0.0f) == !s) sdf[c] = e;
      }
  for (float& v : sdf)
    v = std::clamp(std::isfinite(v) ? v : (v > 0.0f ? 4096.0f : -4096.0f), kSdfRangeMin, kSdfRangeMax);
  return sdf;
}

// grown_attributes.cpp's percentile.
float percentile(std::vector<float> v, float q) {
  if (v.empty()) return 0.0f;
  const size_t k = std::min(v.size() - 1, size_t(q * float(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// Records the asset's update (after `steps` solver steps) in one submission; the update's GPU time (ms).
double update(gpu::Context& ctx, grow_gpu::GpuCloudSolver& solver, grow_gpu::GpuGrownAsset& grown, int steps = 0,
              grow_gpu::GrownUpdateOrder order = grow_gpu::GrownUpdateOrder::Interleaved) {
  gpu::GpuTimer timer(ctx, 1, 8);
  timer.begin_frame(0);
  const auto t0 = std::chrono::steady_clock::now();
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    for (int s = 0; s < steps; ++s) solver.record_step(cmd);
    const uint32_t r = timer.begin(cmd, "grown asset update");
    grown.record_update(cmd, solver, &timer, order);
    timer.end(cmd, r);
  });
  const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<gpu::TimedRange> t = timer.collect(0);
  if (t.empty()) return wall;
  std::string stages;
  for (size_t i = 1; i < t.size(); ++i) stages += strf("%s%s %.1f", i > 1 ? ", " : "", t[i].name.c_str(), t[i].ms);
  std::printf("[ grown_gpu ] update %.1f ms: %s\n", t[0].ms, stages.c_str());
  return t[0].ms;
}

// Differences in 8-bit levels of one channel over the voxels selected: mean, 99th percentile, max.
struct Levels {
  double mean = 0.0;
  int p99 = 0, max = 0;
};
Levels level_differences(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int channel,
                         const std::vector<uint8_t>& selected) {
  std::vector<int> d;
  double sum = 0.0;
  for (size_t i = 0; i < a.size() / 4; ++i)
    if (selected[i]) {
      d.push_back(std::abs(int(a[4 * i + channel]) - int(b[4 * i + channel])));
      sum += d.back();
    }
  Levels l;
  if (d.empty()) return l;
  l.mean = sum / double(d.size());
  l.max = *std::max_element(d.begin(), d.end());
  const size_t k = size_t(0.99 * double(d.size() - 1));
  std::nth_element(d.begin(), d.begin() + long(k), d.end());
  l.p99 = d[k];
  return l;
}

// The stored field of one update against the exact distance of the very mask the GPU made (its resampled cloud
// water, read back): no voxel above it, and on average within the stated error.
void expect_conservative(gpu::Context& ctx, gpu::PipelineLibrary& library, grow_gpu::GpuCloudSolver& solver,
                         const grow_gpu::GrownAssetSettings& settings, const char* what) {
  grow_gpu::GpuGrownAsset grown(ctx, library, solver.dims(), settings);
  const double ms = update(ctx, solver, grown);
  const grow_gpu::GrownAssetGrid& grid = grown.grid();
  const std::vector<float> q = grown.read_cloud_water();
  const std::vector<uint16_t> field = grown.read_field();
  const std::vector<float> flooded = grown.read_distance();
  const std::vector<float> exact = exact_distance(q, grid.voxels, grid.voxel, settings.iso);
  ASSERT_EQ(field.size(), exact.size());
  size_t inside = 0, above = 0, above_quantum = 0, flood_above = 0, band = 0;
  double sum = 0.0, band_sum = 0.0, outside_sum = 0.0, worst = -1e30, flood_worst = 0.0, flood_worst_share = 0.0;
  for (size_t i = 0; i < exact.size(); ++i) {
    const double stored = bake::unorm16_to_field(field[i]), truth = exact[i];
    inside += truth < 0.0;
    above += stored > truth + 1e-3;
    above_quantum += stored > truth + kQuantum;
    worst = std::max(worst, stored - truth);
    sum += truth - stored;
    outside_sum += std::max(truth, 0.0);
    if (std::abs(truth) < 4.0 * grid.voxel) band_sum += truth - stored, ++band;
    // The flood's own distance, before the conservative pass and the margin.
    const double f = std::clamp(double(flooded[i]), double(kSdfRangeMin), double(kSdfRangeMax));
    if (f > truth + 1e-3) {
      ++flood_above;
      flood_worst = std::max(flood_worst, f - truth);
      flood_worst_share = std::max(flood_worst_share, (f - truth) / truth);
    }
  }
  const double voxels = double(exact.size()), mean = sum / voxels, band_mean = band ? band_sum / double(band) : 0.0;
  const double margin_share = settings.safety_fraction * outside_sum / voxels + settings.safety_margin;
  std::printf(
      "[ grown_gpu ] %s, %dx%dx%d voxels of %.0f m, %zu inside, flood +%d: the flood alone %zu voxels above "
      "the exact distance (worst %.3f m, %.2f %% of it); stored %zu above (+1 mm), %zu (+1 quantum), worst "
      "%+.4f m; mean (exact - stored) %.4f m (%.4f m of it the margin), %.4f m within 4 voxels of the surface "
      "(%zu voxels); update %.1f ms\n",
      what, grid.voxels.x, grid.voxels.y, grid.voxels.z, double(grid.voxel), inside, settings.flood_extra_passes,
      flood_above, flood_worst, 100.0 * flood_worst_share, above, above_quantum, worst, mean, margin_share, band_mean,
      band, ms);
  EXPECT_GT(inside, 1000u) << what << ": the check needs a cloud";
  EXPECT_GT(exact.size() - inside, 1000u) << what;
  EXPECT_EQ(above_quantum, 0u) << what
                               << ": voxels whose stored distance exceeds the exact one by more than R16's step";
  EXPECT_EQ(above, 0u) << what << ": voxels whose stored distance exceeds the exact one (by more than float rounding)";
  EXPECT_GE(mean, 0.0) << what;
  EXPECT_LE(mean - margin_share, kFieldMeanError) << what;
  EXPECT_LE(band_mean, kFieldBandError) << what;
}

// Cloud water of one value per cell written straight into the solver's buffer.
void write_cloud_water(gpu::Context& ctx, const grow_gpu::GpuCloudSolver& solver, const std::vector<float>& qc) {
  gpu::Buffer staging(
      ctx, {qc.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, gpu::MemoryUsage::Upload, "test cloud water"});
  std::memcpy(staging.mapped(), qc.data(), qc.size() * sizeof(float));
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, qc.size() * sizeof(float)};
    vkCmdCopyBuffer(cmd, staging.handle(), solver.buffer(Field::CloudWater), 1, &region);
  });
}

}  // namespace

// A cloud stepped on the GPU, at 8 m voxels and at 6 m (125x77x125: a longer flood); then the worst case for jump
// flooding: cloud water drawn at random per cell (a seeded hash, half the cells above the iso), which makes a
// sponge of small pieces and holes, each with its own nearest surface.
TEST(GrowGpu, RegeneratedSdfIsConservative) {
  gpu::Context ctx(validated());
  {
    gpu::PipelineLibrary library(ctx);
    Grown g;
    grow_gpu::GpuCloudSolver solver(ctx, library, g.cpu.settings());
    solver.upload(g.cpu);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
      for (int s = 0; s < 2; ++s) solver.record_step(cmd);
    });
    expect_conservative(ctx, library, solver, grow_gpu::grown_asset_settings(g.spec, 8.0f), "grown cloud");
    expect_conservative(ctx, library, solver, grow_gpu::grown_asset_settings(g.spec, 6.0f), "grown cloud");
    // The usual JFA+2 misses seeds far out on this grid: the 3x3x3 pass and the margin must still hold.
    grow_gpu::GrownAssetSettings weak = grow_gpu::grown_asset_settings(g.spec, 6.0f);
    weak.flood_extra_passes = 2;
    expect_conservative(ctx, library, solver, weak, "grown cloud, JFA+2");

    std::vector<float> sponge(g.cpu.cells());
    uint32_t h = 12345u;
    for (float& q : sponge) {
      h ^= h << 13, h ^= h >> 17, h ^= h << 5;  // xorshift32
      q = g.spec.iso * 2.0f * float(h >> 8) / float(1u << 24);
    }
    write_cloud_water(ctx, solver, sponge);
    expect_conservative(ctx, library, solver, grow_gpu::grown_asset_settings(g.spec, 8.0f), "random sponge");
  }
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}

// The stated tolerances, in 8-bit levels of each modeling channel over the voxels within 3 voxels of the cloud and
// (the means) over all voxels (the CPU derives from the same
// state, uploaded unchanged). The detail type and density scale go through the same arithmetic in the same order,
// so they differ only where float rounding (the device's division, a fused multiply-add) moves a value across a
// level's rounding boundary: by one level, rarely. The profile also reads the distance: where a voxel's cloud water
// lies within rounding of the iso its class can differ, which moves the distance of its neighbourhood by up to a
// voxel, and the profile by up to 255 x 8 m / 12 m levels there; and jump flooding may keep a farther seed for an
// inside voxel. Measured on lavapipe (94x58x94 voxels, 67,696 of them within 3 voxels of the cloud): every channel
// of every voxel the same (mean 0, max 0 levels) and the percentiles bit for bit.
constexpr double kAttributeMean = 0.02;  // levels, mean |GPU - CPU| of the detail type and the density scale
constexpr int kAttributeP99 = 1;
constexpr double kProfileMean = 0.1;  // levels, mean |GPU - CPU| of the profile
constexpr int kProfileP99 = 1;

TEST(GrowGpu, AttributesMatchTheOfflineDerivation) {
  gpu::Context ctx(validated());
  {
    gpu::PipelineLibrary library(ctx);
    Grown g;
    grow_gpu::GpuCloudSolver solver(ctx, library, g.cpu.settings());
    solver.upload(g.cpu);
    grow_gpu::GpuGrownAsset grown(ctx, library, solver.dims(), grow_gpu::grown_asset_settings(g.spec));
    update(ctx, solver, grown);
    const std::vector<uint8_t> gpu_modeling = grown.read_modeling();
    const grow_gpu::GrownAssetGrid& grid = grown.grid();

    // The offline derivation of the same state at the same voxels, encoded as the bake encodes it.
    const grow::GrownCloud cloud = full_box(g.cpu, grid, g.spec.cell_game, g.spec.iso);
    const auto m = grow::derive_modeling(cloud);
    ASSERT_EQ(glm::ivec3(m->sdf.dims), grid.voxels);
    ASSERT_EQ(m->sdf.origin, grid.origin);
    ASSERT_EQ(m->sdf.spacing, grid.voxel);
    const size_t n = grid.count();
    std::vector<uint8_t> cpu_modeling(4 * n);
    auto level = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    size_t cloud_voxels = 0;
    for (size_t i = 0; i < n; ++i) {
      const float field = std::clamp(m->sdf.values[i], kSdfRangeMin, kSdfRangeMax);
      cpu_modeling[4 * i + 0] = level(bake::profile_from_field(field, {m->profile_depth.values[i], 1.0f}));
      cpu_modeling[4 * i + 1] = level(m->detail_type.values[i]);
      cpu_modeling[4 * i + 2] = level(m->density_scale.values[i]);
      cpu_modeling[4 * i + 3] = 0;  // a grown edit's coverage threshold: the recipe's default, 0
      cloud_voxels += field < 0.0f;
    }
    ASSERT_GT(cloud_voxels, 100u) << "the comparison needs a cloud";

    // The percentiles: the same values, bit for bit (a radix select on the GPU, nth_element on the CPU).
    std::vector<float> cpos, wpos, gpos, qin;
    const std::vector<float> w = g.cpu.vertical_velocity();
    for (size_t c = 0; c < g.cpu.cells(); ++c)
      if (g.cpu.cloud_water()[c] > g.spec.iso) {
        cpos.push_back(std::abs(g.cpu.condensation()[c]));
        wpos.push_back(std::abs(w[c]));
        gpos.push_back(std::abs(g.cpu.growth()[c]));
        qin.push_back(g.cpu.cloud_water()[c]);
      }
    const std::array<float, 4> cpu_p = {percentile(cpos, 0.9f), percentile(wpos, 0.9f), percentile(gpos, 0.9f),
                                        percentile(qin, 0.5f)};
    const std::array<float, 4> gpu_p = grown.read_percentiles();
    for (int k = 0; k < 4; ++k) {
      std::printf("[ grown_gpu ] percentile %d over %zu cloud cells: GPU %.9g, CPU %.9g\n", k, qin.size(),
                  double(gpu_p[k]), double(cpu_p[k]));
      EXPECT_EQ(gpu_p[k], cpu_p[k]) << "percentile " << k;
    }
    int evaporating = 0;
    for (size_t c = 0; c < g.cpu.cells(); ++c)
      evaporating += g.cpu.cloud_water()[c] > g.spec.iso && g.cpu.condensation()[c] < 0.0f;
    ASSERT_GT(evaporating, 10) << "the comparison needs evaporating cloud";

    // Compared over the voxels the march reads the modeling at: the cloud and a band of 3 voxels around it (the
    // detail type and density scale are dilated 4 cells beyond the cloud; farther out they are constant).
    std::vector<uint8_t> near(n), all(n, 1);
    size_t near_count = 0;
    for (size_t i = 0; i < n; ++i) near_count += near[i] = m->sdf.values[i] < 3.0f * grid.voxel;
    const char* names[] = {"profile", "detail type", "density scale", "coverage"};
    for (int c = 0; c < 4; ++c) {
      const Levels l = level_differences(gpu_modeling, cpu_modeling, c, near);
      const Levels everywhere = level_differences(gpu_modeling, cpu_modeling, c, all);
      std::printf(
          "[ grown_gpu ] %-13s |GPU - CPU| over %zu voxels near the cloud: mean %.4f, 99th percentile %d, max "
          "%d levels; over all %zu: mean %.4f, max %d\n",
          names[c], near_count, l.mean, l.p99, l.max, n, everywhere.mean, everywhere.max);
      if (c == 0) {
        EXPECT_LE(l.mean, kProfileMean) << names[c];
        EXPECT_LE(l.p99, kProfileP99) << names[c];
      } else if (c < 3) {
        EXPECT_LE(l.mean, kAttributeMean) << names[c];
        EXPECT_LE(l.p99, kAttributeP99) << names[c];
      } else {
        EXPECT_EQ(everywhere.max, 0) << names[c];
      }
      EXPECT_LE(everywhere.mean, c == 0 ? kProfileMean : kAttributeMean) << names[c] << " (all voxels)";
    }
    // Not a flat image: the channels vary across the cloud.
    uint8_t lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], gpu_modeling[4 * i + c]), hi[c] = std::max(hi[c], gpu_modeling[4 * i + c]);
    for (int c = 0; c < 3; ++c) EXPECT_GT(hi[c] - lo[c], 20) << names[c] << " is flat";
  }
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}

// The same state twice, with an empty sky between (nothing of one update may leak into the next: the images'
// texels, the percentiles' histograms), gives the same bytes; three more steps give other bytes.
TEST(GrowGpu, AssetUpdateIsDeterministic) {
  gpu::Context ctx(validated());
  {
    gpu::PipelineLibrary library(ctx);
    Grown g;
    grow_gpu::GpuCloudSolver solver(ctx, library, g.cpu.settings());
    grow_gpu::GpuGrownAsset grown(ctx, library, solver.dims(), grow_gpu::grown_asset_settings(g.spec));
    struct Bytes {
      std::vector<uint8_t> modeling;
      std::vector<uint16_t> field;
    };
    auto read = [&] { return Bytes{grown.read_modeling(), grown.read_field()}; };
    solver.upload(g.cpu);
    const double first_ms = update(ctx, solver, grown);
    const Bytes one = read();

    // An empty sky: every voxel written alike (the images start cleared to other values), far from everything
    // (the field's maximum less the margin), no profile, the attributes' fallback 0.5 (derive_modeling's).
    solver.upload(grow::CloudSolver(g.spec.solver));
    update(ctx, solver, grown);
    const Bytes empty = read();
    const uint16_t far = bake::field_to_unorm16(kSdfRangeMax * (1.0f - grown.settings().safety_fraction));
    size_t other_field = 0, other_modeling = 0;
    for (size_t i = 0; i < empty.field.size(); ++i) {
      other_field += empty.field[i] != far;
      other_modeling += empty.modeling[4 * i] != 0 || empty.modeling[4 * i + 1] != 128 ||
                        empty.modeling[4 * i + 2] != 128 || empty.modeling[4 * i + 3] != 0;
    }
    EXPECT_EQ(other_field, 0u) << "voxels of an empty sky whose field is not " << far;
    EXPECT_EQ(other_modeling, 0u) << "voxels of an empty sky whose modeling is not (0, 128, 128, 0)";

    solver.upload(g.cpu);
    const double ms = update(ctx, solver, grown);
    const Bytes two = read();
    std::printf("[ grown_gpu ] 32x20x32 cells -> %dx%dx%d voxels of %.0f m: update %.2f ms on %s (the first %.2f ms)\n",
                grown.grid().voxels.x, grown.grid().voxels.y, grown.grid().voxels.z, double(grown.grid().voxel), ms,
                ctx.info().name.c_str(), first_ms);
    EXPECT_TRUE(one.modeling == two.modeling) << "modeling bytes differ between two updates of the same state";
    EXPECT_TRUE(one.field == two.field) << "field bytes differ between two updates of the same state";
    // The bench's order (the distance field whole, then the attributes: timed apart) makes the same bytes.
    update(ctx, solver, grown, 0, grow_gpu::GrownUpdateOrder::Apart);
    const Bytes apart = read();
    EXPECT_TRUE(one.modeling == apart.modeling) << "the apart order's modeling differs from the interleaved one's";
    EXPECT_TRUE(one.field == apart.field) << "the apart order's field differs from the interleaved one's";
    EXPECT_FALSE(one.field == empty.field);

    // Spread over frames (the renderer's --cloud-growth-update-frames): each run of stages in a submission of its own,
    // from the empty sky's images. The images keep the empty sky's bytes until the last run, which gives the same
    // bytes as the update in one; a run of a later frame reads only what the runs before it left.
    solver.upload(grow::CloudSolver(g.spec.solver));
    update(ctx, solver, grown);
    solver.upload(g.cpu);
    for (int frames : {2, 4, 7}) {
      const std::vector<grow_gpu::GrownUpdateChunk> chunks = grown.update_chunks(solver, frames);
      ASSERT_EQ(int(chunks.size()), frames);
      int next = 0;
      for (const grow_gpu::GrownUpdateChunk& c : chunks) {
        EXPECT_EQ(c.first, next) << frames << " frames: the runs leave a gap or overlap";
        EXPECT_GT(c.count, 0);
        next = c.first + c.count;
      }
      EXPECT_EQ(chunks.back().count, 1) << "the images' stage is not alone in the last run";
      const int updates = grown.updates_recorded(), stages = grown.stages_recorded();
      for (size_t k = 0; k < chunks.size(); ++k) {
        ctx.submit_and_wait([&](VkCommandBuffer cmd) {
          grown.record_update_stages(cmd, solver, chunks[k].first, chunks[k].count);
        });
        if (k + 1 < chunks.size()) {
          const Bytes during = read();
          EXPECT_TRUE(during.modeling == (frames == 2 ? empty.modeling : one.modeling) &&
                      during.field == (frames == 2 ? empty.field : one.field))
              << frames << " frames: the images changed before the update's last run (run " << k << ")";
          EXPECT_EQ(grown.updates_recorded(), updates);
        }
      }
      EXPECT_EQ(grown.updates_recorded(), updates + 1);
      EXPECT_EQ(grown.stages_recorded(), stages + next);
      const Bytes spread = read();
      EXPECT_TRUE(one.modeling == spread.modeling) << frames << " frames: the modeling differs from one update's";
      EXPECT_TRUE(one.field == spread.field) << frames << " frames: the field differs from one update's";
    }
    const std::vector<grow_gpu::GrownUpdateChunk> whole = grown.update_chunks(solver, 1);
    ASSERT_EQ(whole.size(), 1u);
    EXPECT_EQ(whole[0].first, 0);
    const grow_gpu::GrownAssetView view = grown.view();
    EXPECT_EQ(view.dims, glm::uvec3(grown.grid().voxels));
    EXPECT_EQ(view.field->extent().width, view.dims.x);
    EXPECT_EQ(view.modeling->format(), VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_EQ(view.field->format(), VK_FORMAT_R16_UNORM);
    EXPECT_EQ(view.field->layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

    update(ctx, solver, grown, 3);  // three more steps
    const Bytes later = read();
    EXPECT_FALSE(later.modeling == one.modeling) << "three steps changed nothing in the modeling";
    EXPECT_FALSE(later.field == one.field) << "three steps changed nothing in the field";
  }
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}

TEST(GrowGpu, DISABLED_AssetUpdateTime64x40x64) {
  gpu::Context ctx(validated());
  {
    gpu::PipelineLibrary library(ctx);
    grow::GrowSpec s = grow::parse_grow_spec_text(R"({"preset": "congestus"})", "congestus.json");
    grow::CloudSolver cpu(s.solver);
    for (int i = 0; i < 120; ++i) cpu.step();  // 1200 s: a cloud
    grow_gpu::GpuCloudSolver solver(ctx, library, s.solver);
    solver.upload(cpu);
    grow_gpu::GpuGrownAsset grown(ctx, library, solver.dims(), grow_gpu::grown_asset_settings(s, 8.0f));
    const double first = update(ctx, solver, grown);
    double best = 1e30;
    for (int i = 0; i < 3; ++i) best = std::min(best, update(ctx, solver, grown));
    size_t inside = 0;
    for (uint16_t f : grown.read_field()) inside += bake::unorm16_to_field(f) < 0.0f;
    std::printf(
        "[ grown_gpu ] %dx%dx%d cells of %.0f m -> %dx%dx%d voxels of %.0f m (%zu inside, max qc %.3g): update "
        "%.1f ms on %s (first %.1f ms)\n",
        s.solver.dims.x, s.solver.dims.y, s.solver.dims.z, double(s.cell_game), grown.grid().voxels.x,
        grown.grid().voxels.y, grown.grid().voxels.z, double(grown.grid().voxel), inside, max_abs(cpu.cloud_water()),
        best, ctx.info().name.c_str(), first);
  }
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}
