// The Felzenszwalb-Huttenlocher distance transform (modules/clouds/volume/distance.h) against brute force,
// in voxels and with unequal spacing per axis, and its "no site" convention.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "modules/clouds/volume/distance.h"

namespace cumulo::clouds {
namespace {

TEST(Distance, OneDimensionalMatchesBruteForce) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    const uint32_t n = 1 + rng() % 40;
    std::vector<float> f(n), d(n);
    for (float& v : f) v = (rng() % 3 == 0) ? float(rng() % 50) : kNoSiteDistance2;
    std::vector<int> v(n);
    std::vector<double> z(n + 1);
    const float s = 0.5f + float(rng() % 8);
    squared_distance_1d(f.data(), n, s, d.data(), v.data(), z.data());
    for (int p = 0; p < int(n); ++p) {
      double best = kNoSiteDistance2;
      for (int q = 0; q < int(n); ++q)
        if (f[q] != kNoSiteDistance2) best = std::min(best, double(p - q) * (p - q) * s * s + f[q]);
      if (std::isinf(best)) {
        EXPECT_EQ(d[p], kNoSiteDistance2) << "trial " << trial << " p " << p;
      } else {
        EXPECT_NEAR(d[p], best, 1e-3 * std::max(1.0, best)) << "trial " << trial << " p " << p;
      }
    }
  }
}

TEST(Distance, ThreeDimensionalIsExactWithUnequalSpacing) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 12; ++trial) {
    const glm::uvec3 dims(3 + rng() % 10, 3 + rng() % 10, 3 + rng() % 10);
    const glm::vec3 spacing =
        trial % 2 ? glm::vec3(8.0f) : glm::vec3(1.0f + float(rng() % 4), 2.5f, 1.0f + float(rng() % 3));
    const size_t n = size_t(dims.x) * dims.y * dims.z;
    std::vector<uint8_t> sites(n);
    const int density = 2 + rng() % 30;
    for (auto& s : sites) s = rng() % density == 0;
    if (trial == 3) std::fill(sites.begin(), sites.end(), 0);  // no site at all
    std::vector<float> d = squared_distance_to_mask(sites, dims, spacing);
    ASSERT_EQ(d.size(), n);
    for (uint32_t z = 0; z < dims.z; ++z)
      for (uint32_t y = 0; y < dims.y; ++y)
        for (uint32_t x = 0; x < dims.x; ++x) {
          double best = std::numeric_limits<double>::infinity();
          for (uint32_t k = 0; k < dims.z; ++k)
            for (uint32_t j = 0; j < dims.y; ++j)
              for (uint32_t i = 0; i < dims.x; ++i)
                if (sites[i + dims.x * (j + dims.y * k)]) {
                  glm::dvec3 dv = (glm::dvec3(i, j, k) - glm::dvec3(x, y, z)) * glm::dvec3(spacing);
                  best = std::min(best, glm::dot(dv, dv));
                }
          const float got = d[x + dims.x * (y + dims.y * z)];
          if (std::isinf(best)) {
            EXPECT_EQ(got, kNoSiteDistance2);
          } else {
            EXPECT_NEAR(got, best, 1e-4 * std::max(1.0, best)) << "trial " << trial;
          }
        }
  }
}

TEST(Distance, MatchesBruteForceInVoxels) {
  const glm::uvec3 s{11, 9, 7};
  std::vector<uint8_t> inside(s.x * s.y * s.z, 0);
  for (uint32_t z = 0; z < s.z; ++z)
    for (uint32_t y = 0; y < s.y; ++y)
      for (uint32_t x = 0; x < s.x; ++x) {
        // Two blobs, one touching the border.
        bool in = glm::length(glm::vec3(x, y, z) - glm::vec3(3, 4, 3)) < 2.5f || (x >= 9 && y <= 2);
        inside[(z * s.y + y) * s.x + x] = in;
      }
  std::vector<float> sq = squared_distance_to_mask(inside, s);
  std::vector<float> sdf = signed_distance_from_mask(inside, s, 2.0f);
  for (uint32_t z = 0; z < s.z; ++z)
    for (uint32_t y = 0; y < s.y; ++y)
      for (uint32_t x = 0; x < s.x; ++x) {
        float best_in = 1e30f, best_out = 1e30f;
        for (uint32_t k = 0; k < s.z; ++k)
          for (uint32_t j = 0; j < s.y; ++j)
            for (uint32_t i = 0; i < s.x; ++i) {
              float d2 = float((int(i) - int(x)) * (int(i) - int(x)) + (int(j) - int(y)) * (int(j) - int(y)) +
                               (int(k) - int(z)) * (int(k) - int(z)));
              (inside[(k * s.y + j) * s.x + i] ? best_in : best_out) =
                  std::min(inside[(k * s.y + j) * s.x + i] ? best_in : best_out, d2);
            }
        const size_t idx = (z * s.y + y) * s.x + x;
        ASSERT_FLOAT_EQ(sq[idx], best_in) << x << "," << y << "," << z;
        const float want = inside[idx] ? -(std::sqrt(best_out) * 2.0f - 1.0f) : std::sqrt(best_in) * 2.0f - 1.0f;
        ASSERT_NEAR(sdf[idx], want, 1e-4f);
      }
}

TEST(Distance, EmptyMaskIsInfinite) {
  std::vector<float> sq = squared_distance_to_mask(std::vector<uint8_t>(8, 0), {2, 2, 2});
  for (float v : sq) EXPECT_TRUE(std::isinf(v) && v > 0.0f);
  std::vector<float> scaled = squared_distance_to_mask(std::vector<uint8_t>(8, 0), {2, 2, 2}, {0.5f, 3.0f, 7.0f});
  for (float v : scaled) EXPECT_EQ(v, kNoSiteDistance2);
  // All outside reads +inf, all inside -inf: never NaN.
  for (float v : signed_distance_from_mask(std::vector<uint8_t>(8, 0), {2, 2, 2}, 1.5f)) EXPECT_EQ(v, INFINITY);
  for (float v : signed_distance_from_mask(std::vector<uint8_t>(8, 1), {2, 2, 2}, 1.5f)) EXPECT_EQ(v, -INFINITY);
}

TEST(Distance, SpacingScalesTheDistance) {
  // One site in a line of 5 voxels along each axis in turn: distances are (index * spacing)^2.
  for (int axis = 0; axis < 3; ++axis) {
    glm::uvec3 size(1);
    size[axis] = 5;
    std::vector<uint8_t> mask(5, 0);
    mask[1] = 1;
    glm::vec3 spacing(1.0f);
    spacing[axis] = 0.25f;
    std::vector<float> d = squared_distance_to_mask(mask, size, spacing);
    for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(d[i], float((i - 1) * (i - 1)) * 0.0625f) << "axis " << axis;
  }
}

}  // namespace
}  // namespace cumulo::clouds
