// The generated textures at reduced size (32^3 / 16^3; the 128^3 run is timed by `cumulo noise`):
// tiling across every face of every level, value ranges, smoothness order, determinism, mips.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/error.h"
#include "modules/clouds/noise/noise_textures.h"

namespace cumulo::clouds {
namespace {

struct DiffStats {
  double mean = 0, max = 0;
};

// Differences between neighbours along `axis`: interior pairs (i, i+1) and the seam pair (N-1, 0).
void neighbour_stats(const NoiseTexture& t, int level, int c, int axis, DiffStats* interior, DiffStats* seam) {
  const int n[3] = {t.level_width(level), t.level_height(level), t.level_depth(level)};
  size_t ni = 0, ns = 0;
  *interior = {};
  *seam = {};
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) {
        int q[3] = {x, y, z};
        int i = q[axis];
        q[axis] = (i + 1) % n[axis];
        double d = std::abs(t.at(level, x, y, z, c) - t.at(level, q[0], q[1], q[2], c));
        DiffStats& s = (i == n[axis] - 1) ? *seam : *interior;
        s.mean += d;
        s.max = std::max(s.max, d);
        (i == n[axis] - 1 ? ns : ni) += 1;
      }
  interior->mean /= static_cast<double>(ni);
  seam->mean /= static_cast<double>(ns);
}

// The tiling criterion: the seam (texel N-1 next to texel 0) must look like any interior pair. Per
// plane of pairs (i, i+1) along the axis, the seam plane's mean and max difference must not exceed
// the largest interior plane's by more than 25%. A broken seam is the difference of two unrelated
// texels: 2.5-4x the neighbour difference of these smooth noises (see the NonTilingIsDetected test).
// Axes shorter than 16 texels carry too few planes for statistics and are skipped (a box-filtered
// level of a tiling level tiles by construction; MipsAreBoxAverages checks the filter).
std::string seam_problem(const NoiseTexture& t, int level) {
  const int n[3] = {t.level_width(level), t.level_height(level), t.level_depth(level)};
  for (int c = 0; c < t.channels; ++c)
    for (int axis = 0; axis < 3; ++axis) {
      if (n[axis] < 16) continue;
      std::vector<double> plane_mean(n[axis], 0.0), plane_max(n[axis], 0.0);
      for (int z = 0; z < n[2]; ++z)
        for (int y = 0; y < n[1]; ++y)
          for (int x = 0; x < n[0]; ++x) {
            int q[3] = {x, y, z};
            int i = q[axis];
            q[axis] = (i + 1) % n[axis];
            double d = std::abs(t.at(level, x, y, z, c) - t.at(level, q[0], q[1], q[2], c));
            plane_mean[i] += d;
            plane_max[i] = std::max(plane_max[i], d);
          }
      double worst_mean = 0, worst_max = 0;
      for (int i = 0; i + 1 < n[axis]; ++i) {
        worst_mean = std::max(worst_mean, plane_mean[i]);
        worst_max = std::max(worst_max, plane_max[i]);
      }
      double seam_mean = plane_mean[n[axis] - 1], seam_max = plane_max[n[axis] - 1];
      if (seam_mean > 1.25 * worst_mean + 1e-6 || seam_max > 1.25 * worst_max + 1e-6) {
        size_t pairs = t.level_texels(level) / n[axis];
        return t.name + " level " + std::to_string(level) + " channel " + std::to_string(c) + " axis " +
               std::to_string(axis) + ": seam mean " + std::to_string(seam_mean / pairs) + " max " +
               std::to_string(seam_max) + ", interior planes up to mean " + std::to_string(worst_mean / pairs) +
               " max " + std::to_string(worst_max);
      }
    }
  return {};
}

void expect_tiles(const NoiseTexture& t, int level) { EXPECT_EQ(seam_problem(t, level), ""); }

struct Stats {
  double mean = 0, std = 0, min = 1, max = 0;
};
Stats channel_stats(const NoiseTexture& t, int level, int c) {
  Stats s;
  double sum2 = 0;
  const size_t n = t.level_texels(level);
  for (size_t i = 0; i < n; ++i) {
    double v = t.mips[level][i * t.channels + c];
    s.mean += v;
    sum2 += v * v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.mean /= static_cast<double>(n);
  s.std = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - s.mean * s.mean));
  return s;
}

double roughness(const NoiseTexture& t, int c) {
  DiffStats interior, seam, total;
  for (int axis = 0; axis < 3; ++axis) {
    neighbour_stats(t, 0, c, axis, &interior, &seam);
    total.mean += interior.mean;
  }
  return total.mean;
}

void expect_valid_channels(const NoiseTexture& t) {
  for (int c = 0; c < t.channels; ++c) {
    Stats s = channel_stats(t, 0, c);
    EXPECT_GE(s.min, 0.0) << t.name << " channel " << c;
    EXPECT_LE(s.max, 1.0) << t.name << " channel " << c;
    EXPECT_GT(s.std, 0.05) << t.name << " channel " << c << ": nearly constant";
    EXPECT_GT(s.mean, 0.05) << t.name << " channel " << c;
    EXPECT_LT(s.mean, 0.95) << t.name << " channel " << c;
  }
}

void expect_mips(const NoiseTexture& t) {
  int expected_levels = 1 + static_cast<int>(std::log2(std::max({t.width, t.height, t.depth})));
  ASSERT_EQ(t.levels(), expected_levels) << t.name;
  EXPECT_EQ(t.level_width(t.levels() - 1), 1);
  EXPECT_EQ(t.level_height(t.levels() - 1), 1);
  EXPECT_EQ(t.level_depth(t.levels() - 1), 1);
  for (int level = 1; level < t.levels(); ++level) {
    ASSERT_EQ(t.mips[level].size(), t.level_texels(level) * t.channels);
    EXPECT_EQ(t.level_width(level), std::max(1, t.width >> level));
    for (int c = 0; c < t.channels; ++c)
      EXPECT_NEAR(channel_stats(t, level, c).mean, channel_stats(t, level - 1, c).mean, 1e-4)
          << t.name << " level " << level << " channel " << c;
    expect_tiles(t, level);
  }
}

// Other seeds can be swept by compiling with -DCUMULO_NOISE_TEST_SEED=N (the statistics must hold for any).
#ifndef CUMULO_NOISE_TEST_SEED
#define CUMULO_NOISE_TEST_SEED 1
#endif
constexpr uint64_t kSeed = CUMULO_NOISE_TEST_SEED;

VoxelNoiseParams small_voxel(uint64_t seed = kSeed) {
  VoxelNoiseParams p;
  p.size = 32;
  p.seed = seed;
  return p;
}
SkyNoiseParams small_sky(uint64_t seed = kSeed) {
  SkyNoiseParams p;
  p.base_size = 32;
  p.detail_size = 16;
  p.curl_size = 32;
  p.seed = seed;
  return p;
}

TEST(NoiseTextures, VoxelNoiseTilesHasRangesAndMips) {
  NoiseTexture t = generate_voxel_noise(small_voxel());
  ASSERT_EQ(t.channels, 4);
  ASSERT_EQ(t.width, 32);
  expect_tiles(t, 0);
  expect_valid_channels(t);
  expect_mips(t);
  for (int c = 0; c < 4; ++c) {
    Stats s = channel_stats(t, 0, c);  // normalised to the full range
    EXPECT_FLOAT_EQ(s.min, 0.0f);
    EXPECT_FLOAT_EQ(s.max, 1.0f);
  }
  // R, B low frequency; G, A high frequency.
  EXPECT_LT(roughness(t, 0), roughness(t, 1));
  EXPECT_LT(roughness(t, 2), roughness(t, 3));
  // Curly-Alligator is inverted Alligator: mostly bright, with dark webs; Alligator mostly dark.
  EXPECT_GT(channel_stats(t, 0, 0).mean, 0.5);
  EXPECT_LT(channel_stats(t, 0, 2).mean, 0.5);
}

TEST(NoiseTextures, SkySetTilesHasRangesAndMips) {
  SkyNoiseParams p = small_sky();
  NoiseTexture base = generate_sky_base(p);
  NoiseTexture detail = generate_sky_detail(p);
  NoiseTexture curl2d = generate_curl_2d(p);
  ASSERT_EQ(base.channels, 4);
  ASSERT_EQ(detail.channels, 3);
  ASSERT_EQ(detail.width, 16);
  ASSERT_EQ(curl2d.channels, 3);
  ASSERT_EQ(curl2d.depth, 1);
  for (const NoiseTexture* t : {&base, &detail, &curl2d}) {
    expect_tiles(*t, 0);
    expect_valid_channels(*t);
    expect_mips(*t);
  }
  // Worley at rising frequencies.
  EXPECT_LT(roughness(base, 1), roughness(base, 2));
  EXPECT_LT(roughness(base, 2), roughness(base, 3));
  EXPECT_LT(roughness(detail, 0), roughness(detail, 1));
  EXPECT_LT(roughness(detail, 1), roughness(detail, 2));
  // Curl is signed: stored around 0.5, with the scale kept for decoding.
  EXPECT_GT(curl2d.signed_range, 0.0f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel_stats(curl2d, 0, c).mean, 0.5, 0.15);
}

TEST(NoiseTextures, SameSeedSameTexelsDifferentSeedDifferent) {
  VoxelNoiseParams p = small_voxel(7);
  p.size = 16;
  NoiseTexture a = generate_voxel_noise(p), b = generate_voxel_noise(p);
  EXPECT_EQ(a.mips, b.mips);
  p.seed = 8;
  NoiseTexture c = generate_voxel_noise(p);
  size_t differ = 0;
  for (size_t i = 0; i < a.mips[0].size(); ++i) differ += a.mips[0][i] != c.mips[0][i];
  EXPECT_GT(differ, a.mips[0].size() * 9 / 10);

  SkyNoiseParams s = small_sky(7);
  s.base_size = 16;
  EXPECT_EQ(generate_sky_base(s).mips, generate_sky_base(s).mips);
  EXPECT_EQ(generate_curl_2d(s).mips, generate_curl_2d(s).mips);
  SkyNoiseParams s2 = s;
  s2.seed = 8;
  EXPECT_NE(generate_sky_detail(s).mips, generate_sky_detail(s2).mips);
}

TEST(NoiseTextures, NonTilingIsDetected) {
  // The same Alligator noise sampled over 4 cells of a lattice that repeats every 5 does not tile.
  NoiseTexture t;
  t.name = "broken";
  t.width = t.height = t.depth = 32;
  t.channels = 1;
  fill_texture(
      t,
      [](int x, int y, int z, float* out) {
        out[0] = alligator_fbm(glm::vec3(x + 0.5f, y + 0.5f, z + 0.5f) / 32.0f * 4.0f, 5, 3, 1);
      },
      nullptr);
  normalize_channels(t);
  EXPECT_NE(seam_problem(t, 0), "");
}

TEST(NoiseTextures, MipsAreBoxAverages) {
  NoiseTexture t;
  t.name = "ramp";
  t.width = 4;
  t.height = 2;
  t.depth = 2;
  t.channels = 1;
  fill_texture(t, [](int x, int y, int z, float* out) { out[0] = static_cast<float>(x + 4 * y + 8 * z) / 15.0f; },
               nullptr);
  build_mips(t);
  ASSERT_EQ(t.levels(), 3);
  // Level 1 is 2x1x1: texel 0 averages x in {0,1}, all y, z.
  EXPECT_NEAR(t.at(1, 0, 0, 0, 0), (0.5f + 2.0f + 4.0f) / 15.0f * 1.0f, 1e-6f);
  EXPECT_NEAR(t.at(2, 0, 0, 0, 0), 7.5f / 15.0f, 1e-6f);
  t.width = 3;
  EXPECT_THROW(build_mips(t), Error);
}

TEST(NoiseTextures, RejectsBadSizes) {
  VoxelNoiseParams p;
  p.size = 48;
  EXPECT_THROW(generate_voxel_noise(p), Error);
  SkyNoiseParams s;
  s.detail_size = 2;
  EXPECT_THROW(generate_sky_detail(s), Error);
}

}  // namespace
}  // namespace cumulo::clouds
