// The point noise functions: periodicity, ranges, determinism, analytic gradients, divergence-free
// curl, and the tabulated lattices matching the hashed ones bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "modules/clouds/noise/noise.h"

namespace cumulo::clouds {
namespace {

std::vector<glm::vec3> random_points(int count, float extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, extent);
  std::vector<glm::vec3> out;
  for (int i = 0; i < count; ++i) out.emplace_back(u(rng), u(rng), u(rng));
  return out;
}

// f(p + period * k) == f(p) for the integer shifts k along each axis, including negative ones.
template <typename F>
void expect_periodic(const char* name, int period, F&& f, float tolerance = 2e-4f) {
  const glm::vec3 shifts[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 2, -3}};
  for (glm::vec3 p : random_points(200, static_cast<float>(period), 11)) {
    for (glm::vec3 k : shifts) {
      float a = f(p), b = f(p + k * static_cast<float>(period));
      ASSERT_NEAR(a, b, tolerance) << name << " at (" << p.x << "," << p.y << "," << p.z << ") shift (" << k.x << ","
                                   << k.y << "," << k.z << ")";
    }
  }
}

TEST(Noise, EveryNoiseTilesWithItsPeriod) {
  CurlyAlligatorParams cp;
  expect_periodic("perlin", 4, [](glm::vec3 p) { return perlin(p, 4, 3); });
  expect_periodic("perlin_fbm", 3, [](glm::vec3 p) { return perlin_fbm(p, 3, 4, 3); });
  expect_periodic("worley", 5, [](glm::vec3 p) { return worley(p, 5, 3); });
  expect_periodic("worley_fbm", 4, [](glm::vec3 p) { return worley_fbm(p, 4, 3); });
  expect_periodic("perlin_worley", 4, [](glm::vec3 p) { return perlin_worley(p, 4, 4, 3); });
  expect_periodic("alligator", 6, [](glm::vec3 p) { return alligator(p, 6, 3); });
  expect_periodic("alligator_fbm", 4, [](glm::vec3 p) { return alligator_fbm(p, 4, 3, 3); });
  expect_periodic("curly_alligator", 4, [&](glm::vec3 p) { return curly_alligator(p, 4, cp, 3); });
  for (int axis = 0; axis < 3; ++axis)
    expect_periodic("curl", 4, [axis](glm::vec3 p) { return curl(p, 4, 2, 3)[axis]; }, 2e-3f);
}

TEST(Noise, RangesAndVariation) {
  double sum_all = 0, sum_w = 0;
  float min_all = 1, max_all = 0;
  int n = 0;
  for (glm::vec3 p : random_points(4000, 8.0f, 5)) {
    float a = alligator(p, 8, 1), w = worley(p, 8, 1), pn = perlin(p, 8, 1);
    ASSERT_GE(a, 0.0f);
    ASSERT_LT(a, 1.0f);
    ASSERT_GE(w, 0.0f);
    ASSERT_LE(w, 1.0f);
    ASSERT_LE(std::abs(pn), 1.1f);
    float wf = worley_fbm(p, 8, 1);
    ASSERT_GE(wf, 0.0f);
    ASSERT_LE(wf, 1.0f);
    float pw = perlin_worley(p, 8, 4, 1);
    ASSERT_GE(pw, 0.0f);
    ASSERT_LE(pw, 1.0f);
    sum_all += a;
    sum_w += w;
    min_all = std::min(min_all, a);
    max_all = std::max(max_all, a);
    ++n;
  }
  // Not constant, not degenerate: Alligator spans most of its range, Worley F1 averages ~0.5 cells.
  EXPECT_LT(min_all, 0.02f);
  EXPECT_GT(max_all, 0.5f);
  EXPECT_GT(sum_all / n, 0.05);
  EXPECT_NEAR(sum_w / n, 0.5, 0.15);
}

TEST(Noise, DeterministicAndSeedDependent) {
  int differ = 0;
  for (glm::vec3 p : random_points(100, 4.0f, 9)) {
    EXPECT_EQ(alligator(p, 4, 42), alligator(p, 4, 42));
    EXPECT_EQ(perlin(p, 4, 42), perlin(p, 4, 42));
    if (alligator(p, 4, 42) != alligator(p, 4, 43)) ++differ;
  }
  EXPECT_GT(differ, 80);
  EXPECT_NE(derive_seed(1, 0), derive_seed(2, 0));
  EXPECT_NE(derive_seed(1, 0), derive_seed(1, 1));
  EXPECT_NE(derive_seed(1, 0), derive_seed(1ull << 32 | 1, 0));
}

TEST(Noise, PerlinGradientMatchesFiniteDifferences) {
  const float h = 1e-3f;
  for (glm::vec3 p : random_points(200, 4.0f, 3)) {
    glm::vec4 g = perlin_fbm_grad(p, 4, 3, 7);
    EXPECT_FLOAT_EQ(g.w, perlin_fbm(p, 4, 3, 7));
    for (int a = 0; a < 3; ++a) {
      glm::vec3 d(0.0f);
      d[a] = h;
      float fd = (perlin_fbm(p + d, 4, 3, 7) - perlin_fbm(p - d, 4, 3, 7)) / (2 * h);
      EXPECT_NEAR(g[a], fd, 0.02f) << "axis " << a;
    }
  }
}

TEST(Noise, CurlIsDivergenceFree) {
  const float h = 1e-2f;
  double div_sum = 0, mag_sum = 0;
  for (glm::vec3 p : random_points(200, 4.0f, 13)) {
    float div = 0;
    for (int a = 0; a < 3; ++a) {
      glm::vec3 d(0.0f);
      d[a] = h;
      div += (curl(p + d, 4, 2, 5)[a] - curl(p - d, 4, 2, 5)[a]) / (2 * h);
    }
    glm::vec3 c = curl(p, 4, 2, 5);
    div_sum += std::abs(div);
    mag_sum += std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  }
  // |div| is finite-difference error only; a non-solenoidal field of this size would give ~|curl|/cell.
  EXPECT_LT(div_sum, 0.02 * mag_sum);
  EXPECT_GT(mag_sum / 200, 0.1);
}

TEST(Noise, TabulatedLatticesMatchHashedFunctions) {
  const FeatureLattice lattice(5, 77);
  const WorleyFbm wf(3, 77);
  const AlligatorFbm af(3, 3, 77, 0.5f);
  CurlyAlligatorParams cp;
  const CurlyAlligator ca(4, cp, 77);
  for (glm::vec3 p : random_points(300, 10.0f, 21)) {
    EXPECT_EQ(worley(p, lattice), worley(p, 5, 77));
    EXPECT_EQ(alligator(p, lattice), alligator(p, 5, 77));
    EXPECT_EQ(wf(p), worley_fbm(p, 3, 77));
    EXPECT_EQ(af(p), alligator_fbm(p, 3, 3, 77, 0.5f));
    EXPECT_EQ(ca(p), curly_alligator(p, 4, cp, 77));
  }
}

TEST(Noise, CurlyAlligatorIsDistortedInvertedAlligator) {
  CurlyAlligatorParams cp;
  CurlyAlligatorParams none = cp;
  none.curl_strength = 0.0f;
  int distorted = 0;
  for (glm::vec3 p : random_points(200, 4.0f, 8)) {
    // Without distortion it is exactly 1 - Alligator fBm.
    EXPECT_FLOAT_EQ(curly_alligator(p, 4, none, 3), 1.0f - alligator_fbm(p, 4, cp.octaves, 3, cp.gain));
    glm::vec3 w = curly_alligator_warp(p, 4, cp, 3);
    EXPECT_FLOAT_EQ(curly_alligator(p, 4, cp, 3), 1.0f - alligator_fbm(p + w, 4, cp.octaves, 3, cp.gain));
    if (std::abs(w.x) + std::abs(w.y) + std::abs(w.z) > 0.05f) ++distorted;
  }
  EXPECT_GT(distorted, 100);
}

}  // namespace
}  // namespace cumulo::clouds
