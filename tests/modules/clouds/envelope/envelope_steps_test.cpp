// The envelope's step data against brute force on small random maps: the distance transform, the dilation, edge_m,
// the 3x3 conservative top and bottom, the cone ratios (the header's definition over every pair of texels, and no
// lower than needed), the distance step; then the march's own rule (envelope_march.comp) never skips a density.
#include "modules/clouds/envelope/envelope_steps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "modules/clouds/envelope/envelope_bake.h"

using namespace cumulo::clouds::envelope;

namespace {

constexpr double kSqrt2 = 1.4142135623730951;

// Random blobs and scattered texels with rough, unrelated heights: the hardest case for the cones.
EnvelopeMaps random_shape(uint32_t n, float texel_m, uint32_t seed, int blobs = 6, float scatter = 0.03f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  EnvelopeMaps m;
  m.resolution = n;
  m.texel_m = texel_m;
  m.origin = glm::vec2(-100.0f, 250.0f);
  m.edge_width_m = 2.0f * texel_m;
  std::vector<glm::vec3> discs;
  for (int b = 0; b < blobs; ++b) discs.emplace_back(u(rng) * float(n), u(rng) * float(n), 2.0f + 6.0f * u(rng));
  m.shape.assign(size_t(n) * n, glm::vec4(0.0f));
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      bool covered = u(rng) < scatter;
      for (const glm::vec3& d : discs)
        covered = covered || glm::distance(glm::vec2(float(i), float(j)), glm::vec2(d)) < d.z;
      const float bottom = 50.0f + 250.0f * u(rng);
      const float top = bottom + 10.0f + 390.0f * u(rng);
      const float coverage = 0.1f + 0.9f * u(rng), detail = u(rng);
      if (covered) m.shape[size_t(j) * n + i] = glm::vec4(bottom, top, coverage, detail);
    }
  return m;
}

double centre_distance(int di, int dj) { return std::sqrt(double(di) * di + double(dj) * dj); }

// The smallest distance between the squares of two texels (di, dj) apart, in texels.
double square_distance(int di, int dj) {
  const double ax = std::max(std::abs(di) - 1, 0), ay = std::max(std::abs(dj) - 1, 0);
  return std::sqrt(ax * ax + ay * ay);
}

// The brute-force minimum of the header's cone ratio for texel i (its apex a) over values v (capped).
double brute_ratio(float a, const std::vector<float>& v, uint32_t n, double texel, size_t i) {
  double best = kMaxConeRatio;
  const int ix = int(i % n), iy = int(i / n);
  for (size_t k = 0; k < v.size(); ++k) {
    if (!(v[k] > a)) continue;
    const double d = square_distance(int(k % n) - ix, int(k / n) - iy) * texel;
    best = std::min(best, d / (double(v[k]) - double(a)));
  }
  return best;
}

void check_against_brute_force(EnvelopeMaps m) {
  const uint32_t n = m.resolution;
  const size_t count = size_t(n) * n;
  const double texel = m.texel_m;
  const std::vector<glm::vec4> painted = m.shape;
  derive_envelope_steps(m);
  ASSERT_EQ(m.shape.size(), count);
  ASSERT_EQ(m.steps.size(), count);
  ASSERT_EQ(m.distance_m.size(), count);
  ASSERT_EQ(m.edge_m.size(), count);
  std::vector<size_t> covered;
  for (size_t k = 0; k < count; ++k)
    if (painted[k].z > 0.0f) covered.push_back(k);
  auto ix = [n](size_t k) { return int(k % n); };
  auto iy = [n](size_t k) { return int(k / n); };

  // Shape: covered texels unchanged; empty ones hold a nearest covered texel's heights, coverage 0; edge_m.
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (size_t k = 0; k < count; ++k) {
    if (painted[k].z > 0.0f) {
      EXPECT_EQ(m.shape[k], painted[k]);
      lo = std::min(lo, painted[k].x);
      hi = std::max(hi, painted[k].y);
      double d = std::min({ix(k) + 1.0, double(n) - ix(k), iy(k) + 1.0, double(n) - iy(k)});  // the border
      for (size_t o = 0; o < count; ++o)
        if (!(painted[o].z > 0.0f)) d = std::min(d, centre_distance(ix(o) - ix(k), iy(o) - iy(k)));
      EXPECT_NEAR(m.edge_m[k], (d - 0.5) * texel, 1e-3) << k;
      EXPECT_GT(m.edge_m[k], 0.0f);
      continue;
    }
    EXPECT_EQ(m.shape[k].z, 0.0f);
    if (covered.empty()) {
      EXPECT_EQ(m.edge_m[k], -kFarDistanceM);
      continue;
    }
    double d = 1e30;
    for (size_t c : covered) d = std::min(d, centre_distance(ix(c) - ix(k), iy(c) - iy(k)));
    bool from_nearest = false;
    for (size_t c : covered)
      from_nearest = from_nearest || (centre_distance(ix(c) - ix(k), iy(c) - iy(k)) == d &&
                                      painted[c].x == m.shape[k].x && painted[c].y == m.shape[k].y);
    EXPECT_TRUE(from_nearest) << k;
    EXPECT_NEAR(m.edge_m[k], -(d - 0.5) * texel, 1e-3) << k;
    EXPECT_LT(m.edge_m[k], 0.0f);
  }
  if (!covered.empty()) {
    EXPECT_EQ(m.min_bottom, lo);
    EXPECT_EQ(m.max_top, hi);
  }

  // Tc, Bc over the 3x3 (dilated heights included where the 3x3 holds coverage).
  std::vector<float> tc(count), bc(count);
  std::vector<size_t> near;
  for (size_t k = 0; k < count; ++k) {
    bool has = false;
    float t = std::numeric_limits<float>::lowest(), b = std::numeric_limits<float>::max();
    for (int y = std::max(iy(k) - 1, 0); y <= std::min(iy(k) + 1, int(n) - 1); ++y)
      for (int x = std::max(ix(k) - 1, 0); x <= std::min(ix(k) + 1, int(n) - 1); ++x) {
        const size_t o = size_t(y) * n + size_t(x);
        has = has || painted[o].z > 0.0f;
        t = std::max(t, m.shape[o].y);
        b = std::min(b, m.shape[o].x);
      }
    tc[k] = has ? t : kEmptyTop;
    bc[k] = has ? b : kEmptyBottom;
    EXPECT_EQ(m.steps[k].x, tc[k]) << k;
    EXPECT_EQ(m.steps[k].y, bc[k]) << k;
    if (has) near.push_back(k);
  }

  // Apexes: the 3x3's highest Tc and lowest Bc.
  std::vector<float> at(count), ab(count), neg_ab(count), neg_bc(count);
  for (size_t k = 0; k < count; ++k) {
    float t = tc[k], b = bc[k];
    for (int y = std::max(iy(k) - 1, 0); y <= std::min(iy(k) + 1, int(n) - 1); ++y)
      for (int x = std::max(ix(k) - 1, 0); x <= std::min(ix(k) + 1, int(n) - 1); ++x) {
        const size_t o = size_t(y) * n + size_t(x);
        if (tc[o] > kEmptyTop) t = std::max(t, tc[o]);
        if (bc[o] < kEmptyBottom) b = std::min(b, bc[o]);
      }
    at[k] = t, ab[k] = b;
    EXPECT_EQ(m.apex[k].x, t) << k;
    EXPECT_EQ(m.apex[k].y, b) << k;
    neg_ab[k] = -b;
    neg_bc[k] = -bc[k];
  }
  // Cones: the definition over every pair, and as large as it may be.
  for (size_t i = 0; i < count; ++i) {
    const double z = m.steps[i].z, w = m.steps[i].w;
    ASSERT_GE(z, 0.0);
    ASSERT_LE(z, double(kMaxConeRatio));
    ASSERT_GE(w, 0.0);
    ASSERT_LE(w, double(kMaxConeRatio));
    for (size_t k = 0; k < count; ++k) {
      const double dist = square_distance(ix(k) - ix(i), iy(k) - iy(i)) * texel;
      if (tc[k] > at[i]) {
        ASSERT_GE(dist, z * (double(tc[k]) - double(at[i]))) << i << " -> " << k;
      }
      if (bc[k] < ab[i]) {
        ASSERT_GE(dist, w * (double(ab[i]) - double(bc[k]))) << i << " -> " << k;
      }
    }
    const double bz = brute_ratio(at[i], tc, n, texel, i), bw = brute_ratio(neg_ab[i], neg_bc, n, texel, i);
    EXPECT_GE(z, bz * (1.0 - 1e-5)) << i;
    EXPECT_GE(w, bw * (1.0 - 1e-5)) << i;
  }

  // The distance step: a lower bound from any point of the texel to any point of a texel whose 3x3 holds coverage
  // (the squares' exact distance), and the centres' bound less sqrt(2) texels, no lower.
  for (size_t i = 0; i < count; ++i) {
    if (near.empty()) {
      EXPECT_EQ(m.distance_m[i], kFarDistanceM);
      continue;
    }
    double square = 1e30, centre = 1e30;
    for (size_t k : near) {
      const int dx = std::abs(ix(k) - ix(i)), dy = std::abs(iy(k) - iy(i));
      square = std::min(square, std::hypot(std::max(dx - 1, 0) * texel, std::max(dy - 1, 0) * texel));
      centre = std::min(centre, centre_distance(dx, dy));
    }
    ASSERT_LE(double(m.distance_m[i]), square) << i;
    EXPECT_GE(double(m.distance_m[i]), std::max(0.0, centre - kSqrt2) * texel * (1.0 - 1e-6)) << i;
  }
}

}  // namespace

TEST(EnvelopeSteps, DistanceTransformIsExact) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float density : {0.0f, 0.002f, 0.05f, 0.5f, 1.0f}) {
    const uint32_t n = 37;
    std::vector<uint8_t> site(size_t(n) * n);
    for (auto& s : site) s = u(rng) < density;
    const DistanceField f = distance_transform(site, n);
    for (size_t q = 0; q < site.size(); ++q) {
      double best = kNoSite;
      for (size_t p = 0; p < site.size(); ++p)
        if (site[p]) {
          const double dx = double(p % n) - double(q % n), dy = double(p / n) - double(q / n);
          best = std::min(best, dx * dx + dy * dy);
        }
      ASSERT_EQ(f.d2[q], best) << "density " << density << " texel " << q;
      if (best >= kNoSite) {
        EXPECT_EQ(f.nearest[q], -1);
        continue;
      }
      ASSERT_GE(f.nearest[q], 0);
      const size_t p = size_t(f.nearest[q]);
      EXPECT_TRUE(site[p]);
      const double dx = double(p % n) - double(q % n), dy = double(p / n) - double(q / n);
      EXPECT_EQ(dx * dx + dy * dy, best);
    }
  }
}

TEST(EnvelopeSteps, RandomMapsMatchBruteForce) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    check_against_brute_force(random_shape(48, 7.3f, seed));
  }
}

TEST(EnvelopeSteps, SmallAndDegenerateMaps) {
  check_against_brute_force(random_shape(16, 50.0f, 4, 0, 0.0f));  // nothing covered
  check_against_brute_force(random_shape(16, 2.0f, 5, 0, 0.01f));  // a few single texels
  check_against_brute_force(random_shape(17, 3.0f, 6, 3, 0.9f));   // nearly everything, odd size
}

// envelope_march.comp's rule, replayed on the CPU: above the conservative top (under the bottom) of its texel a
// point may jump to where it leaves the cone, or by the distance step; nothing on the way may hold density.
TEST(EnvelopeSteps, TheMarchsJumpsNeverSkipDensity) {
  EnvelopeMaps m = random_shape(48, 7.3f, 11);
  derive_envelope_steps(m);
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float side = float(m.resolution) * m.texel_m;
  int jumps = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const glm::vec3 p(m.origin.x + side * u(rng), -100.0f + 700.0f * u(rng), m.origin.y + side * u(rng));
    glm::vec3 d(u(rng) - 0.5f, (u(rng) - 0.5f) * (u(rng) < 0.5f ? 0.2f : 2.0f), u(rng) - 0.5f);
    d = glm::normalize(d);
    const uint32_t i = std::min(uint32_t((p.x - m.origin.x) / m.texel_m), m.resolution - 1);
    const uint32_t j = std::min(uint32_t((p.z - m.origin.y) / m.texel_m), m.resolution - 1);
    const glm::vec4 s = m.steps[size_t(j) * m.resolution + i];
    if (!(p.y > s.x || p.y < s.y)) continue;
    const float horizontal = glm::length(glm::vec2(d.x, d.z));
    auto cone = [&](float h, float ratio, float up) {
      const float denom = horizontal - ratio * up;
      return denom > 1e-6f ? ratio * h / denom : 1e9f;
    };
    const glm::vec2 a = m.apex[size_t(j) * m.resolution + i];
    float jump = 0.0f;
    if (p.y > a.x) jump = cone(p.y - a.x, s.z, d.y);
    if (p.y < a.y) jump = std::max(jump, cone(a.y - p.y, s.w, -d.y));
    if (horizontal > 1e-4f) jump = std::max(jump, m.distance_m[size_t(j) * m.resolution + i] / horizontal);
    jump = std::min(jump, 2.0f * side);
    if (jump <= 0.0f) continue;
    ++jumps;
    for (int k = 0; k < 400; ++k) {
      const glm::vec3 q = p + d * (jump * float(k) / 400.0f);
      ASSERT_EQ(sample_envelope(m, q).profile, 0.0f) << "trial " << trial << " step " << k << " of a jump of " << jump;
    }
  }
  EXPECT_GT(jumps, 1000);
}
