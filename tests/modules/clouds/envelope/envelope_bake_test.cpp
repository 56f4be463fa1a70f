// The Envelope method's bake over an analytic terrain (a Gaussian peak): the talk's profile, each rule's footprint
// and heights, their union, the global coverage, the ceiling, painted maps (8 and 16 bits), the CPU density query
// against the step data, and the bake's time at resolution 256.
#include "modules/clouds/envelope/envelope_bake.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "engine/core/png.h"
#include "tests/modules/clouds/envelope/grey_png16.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
using namespace cumulo::clouds::envelope;

namespace {

constexpr glm::vec2 kPeak{300.0f, 200.0f};
constexpr float kPeakHeight = 400.0f, kSigma = 250.0f;

float gaussian_terrain(float x, float z) {
  const glm::vec2 d = glm::vec2(x, z) - kPeak;
  return kPeakHeight * std::exp(-glm::dot(d, d) / (2.0f * kSigma * kSigma));
}

OrographicClouds spec_with(std::vector<EnvelopeRule> rules, uint32_t resolution = 128) {
  OrographicClouds c;
  c.extent_min = glm::vec2(-1000.0f);
  c.extent_max = glm::vec2(1000.0f);
  c.resolution = resolution;
  c.rules = std::move(rules);
  return c;
}

EnvelopeRule cap_at_peak(float radius, float base, float top, float coverage = 1.0f) {
  EnvelopeRule r;
  r.kind = CapRule{true, glm::vec2(0.0f), radius, base, top};
  r.coverage = coverage;
  return r;
}

glm::vec2 centre(const EnvelopeMaps& m, size_t k) {
  return m.origin + (glm::vec2(float(k % m.resolution), float(k / m.resolution)) + 0.5f) * m.texel_m;
}

size_t texel_at(const EnvelopeMaps& m, glm::vec2 p) {
  const glm::uvec2 t = glm::uvec2((p - m.origin) / m.texel_m);
  return size_t(t.y) * m.resolution + t.x;
}

}  // namespace

TEST(EnvelopeProfile, FollowsTheTalksGradients) {
  EXPECT_FLOAT_EQ(kProfilePeak, float(std::pow(3.0 / 7.0, 1.5) * std::pow(4.0 / 7.0, 2.0)));
  const float b = 100.0f, t = 450.0f, edge = 35.0f;
  auto at = [&](float hf, float e = 1000.0f, float c = 1.0f) {
    return envelope_profile(b + hf * (t - b), b, t, e, edge, c);
  };
  EXPECT_NEAR(at(4.0f / 7.0f), 1.0f, 1e-5f);  // the peak, normalised
  float best = 0.0f, arg = 0.0f;
  for (int i = 1; i < 10000; ++i) {
    const float hf = float(i) / 10000.0f;
    if (at(hf) > best) best = at(hf), arg = hf;
  }
  EXPECT_LE(best, 1.0f + 1e-5f);
  EXPECT_NEAR(arg, 4.0f / 7.0f, 1e-3f);
  for (float hf : {0.05f, 0.3f, 0.5f, 0.8f, 0.97f}) {
    const float talk = std::pow(1.0f - hf, 1.5f) * std::pow(hf, 2.0f);  // top_gradient * bottom_gradient
    EXPECT_NEAR(at(hf), talk / kProfilePeak, 1e-5f) << hf;
    EXPECT_NEAR(at(hf, 17.5f), 0.5f * talk / kProfilePeak, 1e-5f) << hf;  // half way into the edge band
    EXPECT_NEAR(at(hf, 1000.0f, 0.25f), 0.25f * talk / kProfilePeak, 1e-5f) << hf;
  }
  EXPECT_EQ(at(0.0f), 0.0f);
  EXPECT_EQ(at(1.0f), 0.0f);
  EXPECT_EQ(at(-0.2f), 0.0f);
  EXPECT_EQ(at(1.3f), 0.0f);
  EXPECT_EQ(at(0.5f, 0.0f), 0.0f);    // at the side
  EXPECT_EQ(at(0.5f, -10.0f), 0.0f);  // outside
  EXPECT_EQ(at(0.5f, 1000.0f, 0.0f), 0.0f);
  EXPECT_EQ(envelope_profile(200.0f, 300.0f, 300.0f, 100.0f, 35.0f, 1.0f), 0.0f);
}

TEST(EnvelopeBake, CapSitsOnThePeak) {
  const EnvelopeMaps m = bake_envelope_maps(spec_with({cap_at_peak(300.0f, 350.0f, 600.0f)}), gaussian_terrain);
  EXPECT_EQ(m.resolution, 128u);
  EXPECT_EQ(m.origin, glm::vec2(-1000.0f));
  EXPECT_FLOAT_EQ(m.texel_m, 2000.0f / 128.0f);
  EXPECT_FLOAT_EQ(m.min_bottom, 350.0f);
  EXPECT_FLOAT_EQ(m.max_top, 600.0f);
  const glm::vec4 at_peak = m.shape[texel_at(m, kPeak)];
  EXPECT_FLOAT_EQ(at_peak.z, 1.0f);
  EXPECT_FLOAT_EQ(at_peak.x, 350.0f);
  EXPECT_FLOAT_EQ(at_peak.y, 600.0f);
  const float mid = m.shape[texel_at(m, kPeak + glm::vec2(230.0f, 0.0f))].z;
  EXPECT_GT(mid, 0.0f);
  EXPECT_LT(mid, 1.0f);
  size_t footprint = 0;
  for (size_t k = 0; k < m.shape.size(); ++k)
    if (m.shape[k].z > 0.0f) {
      ++footprint;
      EXPECT_LT(glm::distance(centre(m, k), kPeak), 300.0f + m.texel_m) << k;
    }
  // The disc of radius 300 m, in texels.
  EXPECT_NEAR(double(footprint), 3.14159 * 300.0 * 300.0 / (m.texel_m * m.texel_m), 40.0);
}

TEST(EnvelopeBake, TheCapIsADomeAndVariationRoughensItsTop) {
  EnvelopeRule cap = cap_at_peak(300.0f, 350.0f, 600.0f);
  const EnvelopeMaps smooth = bake_envelope_maps(spec_with({cap}), gaussian_terrain);
  float last = 1e9f;
  for (float d = 0.0f; d < 280.0f; d += 40.0f) {  // the top comes down toward the side
    const float top = smooth.shape[texel_at(smooth, kPeak + glm::vec2(d, 0.0f))].y;
    EXPECT_LE(top, last + 1e-3f) << d;
    last = top;
  }
  EXPECT_LT(last, 570.0f);  // 560 m at 240 m out
  cap.variation = 0.6f;
  cap.variation_m = 80.0f;
  const EnvelopeMaps rough = bake_envelope_maps(spec_with({cap}), gaussian_terrain);
  const EnvelopeMaps again = bake_envelope_maps(spec_with({cap}), gaussian_terrain);
  double spread = 0.0, thinner = 0.0;
  int n = 0;
  for (size_t k = 0; k < rough.shape.size(); ++k) {
    ASSERT_EQ(rough.shape[k], again.shape[k]) << k;  // deterministic
    if (!(smooth.shape[k].z > 0.0f) || !(rough.shape[k].z > 0.0f)) continue;
    const double d = double(rough.shape[k].y) - double(smooth.shape[k].y);
    spread += d * d;
    thinner += smooth.shape[k].z - rough.shape[k].z;
    EXPECT_GE(rough.shape[k].y - rough.shape[k].x, kMinThicknessM - 1e-3f) << k;
    ++n;
  }
  ASSERT_GT(n, 100);
  EXPECT_GT(std::sqrt(spread / n), 15.0);  // metres of lumps on a 250 m thick cap
  EXPECT_GT(thinner / n, 0.02);           // and gaps where the top comes down
}

TEST(EnvelopeBake, BankHugsTheWindwardSlope) {
  EnvelopeRule r;
  r.kind = BankRule{glm::vec3(-1.0f, 0.0f, 0.0f), glm::vec2(50.0f, 300.0f), 20.0f, 150.0f};  // the wind blows to +x
  r.coverage = 0.9f;
  const EnvelopeMaps m = bake_envelope_maps(spec_with({r}), gaussian_terrain);
  const glm::vec2 windward = kPeak - glm::vec2(250.0f, 0.0f), lee = kPeak + glm::vec2(250.0f, 0.0f);
  const glm::vec4 w = m.shape[texel_at(m, windward)];
  EXPECT_GT(w.z, 0.6f);  // within the band's fading quarter there: not all of the rule's 0.9
  EXPECT_LE(w.z, 0.9f + 1e-6f);
  const glm::vec2 c = centre(m, texel_at(m, windward));
  EXPECT_NEAR(w.x, gaussian_terrain(c.x, c.y) + 20.0f, 1e-3f);
  EXPECT_NEAR(w.y, gaussian_terrain(c.x, c.y) + 170.0f, 1e-3f);
  EXPECT_EQ(m.shape[texel_at(m, lee)].z, 0.0f);
  EXPECT_EQ(m.shape[texel_at(m, kPeak + glm::vec2(0.0f, 600.0f))].z, 0.0f);  // too low
  for (size_t k = 0; k < m.shape.size(); ++k)
    if (m.shape[k].z > 0.0f) {
      const glm::vec2 p = centre(m, k);
      EXPECT_LT(p.x, kPeak.x) << k;  // only where the ground rises along the wind
      EXPECT_GT(gaussian_terrain(p.x, p.y), 50.0f) << k;
      EXPECT_LT(gaussian_terrain(p.x, p.y), 300.0f) << k;
    }
}

TEST(EnvelopeBake, LayerFillsTheLowlandsAndRegionsBoundRules) {
  EnvelopeRule r;
  r.kind = LayerRule{60.0f, 5.0f, 30.0f};
  const EnvelopeMaps m = bake_envelope_maps(spec_with({r}), gaussian_terrain);
  const glm::vec4 low = m.shape[texel_at(m, glm::vec2(-800.0f, -800.0f))];
  EXPECT_FLOAT_EQ(low.z, 1.0f);
  EXPECT_NEAR(low.x, 5.0f, 1e-3f);
  EXPECT_FLOAT_EQ(low.y, 60.0f);
  EXPECT_EQ(m.shape[texel_at(m, kPeak)].z, 0.0f);
  for (size_t k = 0; k < m.shape.size(); ++k)
    if (m.shape[k].z > 0.0f) {
      EXPECT_LT(gaussian_terrain(centre(m, k).x, centre(m, k).y), 30.0f) << k;
    }

  r.region = EnvelopeRegion{glm::vec2(-500.0f, -500.0f), 200.0f};
  const EnvelopeMaps bounded = bake_envelope_maps(spec_with({r}), gaussian_terrain);
  EXPECT_FLOAT_EQ(bounded.shape[texel_at(bounded, glm::vec2(-500.0f, -500.0f))].z, 1.0f);
  EXPECT_EQ(bounded.shape[texel_at(bounded, glm::vec2(-800.0f, -800.0f))].z, 0.0f);
  for (size_t k = 0; k < bounded.shape.size(); ++k)
    if (bounded.shape[k].z > 0.0f) {
      EXPECT_LT(glm::distance(centre(bounded, k), glm::vec2(-500.0f)), 200.0f) << k;
    }
}

TEST(EnvelopeBake, RulesUniteAndTheCoverageScalesThem) {
  EnvelopeRule a = cap_at_peak(300.0f, 100.0f, 300.0f, 0.5f), b = cap_at_peak(300.0f, 200.0f, 500.0f, 0.9f);
  a.detail_type = 0.0f;
  b.detail_type = 1.0f;
  OrographicClouds spec = spec_with({a, b});
  const EnvelopeMaps both = bake_envelope_maps(spec, gaussian_terrain);
  const glm::vec4 s = both.shape[texel_at(both, kPeak)];
  EXPECT_NEAR(s.x, (0.5f * 100.0f + 0.9f * 200.0f) / 1.4f, 1e-3f);  // coverage-weighted heights
  EXPECT_NEAR(s.y, (0.5f * 300.0f + 0.9f * 500.0f) / 1.4f, 1e-3f);
  EXPECT_FLOAT_EQ(s.z, 0.9f);
  EXPECT_NEAR(s.w, 0.9f / 1.4f, 1e-5f);  // coverage-weighted
  spec.coverage = 0.5f;
  const EnvelopeMaps half = bake_envelope_maps(spec, gaussian_terrain);
  EXPECT_FLOAT_EQ(half.shape[texel_at(half, kPeak)].z, 0.45f);
  spec.coverage = 0.0f;
  const EnvelopeMaps none = bake_envelope_maps(spec, gaussian_terrain);
  for (const glm::vec4& t : none.shape) ASSERT_EQ(t.z, 0.0f);
  for (const glm::vec4& t : none.steps) ASSERT_EQ(t.x, kEmptyTop);
}

TEST(EnvelopeBake, CeilingClampsTheTop) {
  const OrographicClouds spec = spec_with({cap_at_peak(300.0f, 350.0f, 600.0f)});
  // Voxel clouds at 500 m west of the peak and at 375 m east of it; none north.
  auto ceiling = [](float x, float z) {
    if (z > kPeak.y + 100.0f) return std::numeric_limits<float>::infinity();
    return x < kPeak.x ? 500.0f : 375.0f;
  };
  float reported = -1.0f;
  const EnvelopeMaps m = bake_envelope_maps(spec, gaussian_terrain, ceiling, [&](float f) { reported = f; });
  EXPECT_EQ(reported, 1.0f);
  const glm::vec4 west = m.shape[texel_at(m, kPeak + glm::vec2(-100.0f, 0.0f))];
  EXPECT_FLOAT_EQ(west.y, 480.0f);
  EXPECT_GT(west.z, 0.0f);
  EXPECT_EQ(m.shape[texel_at(m, kPeak + glm::vec2(100.0f, 0.0f))].z, 0.0f);  // 355 m: less than 10 m left
  // North, no ceiling: the cap's dome, 60 % of the thickness at the radius and all of it over the peak.
  const size_t north = texel_at(m, kPeak + glm::vec2(0.0f, 150.0f));
  const float f = glm::distance(centre(m, north), kPeak) / 300.0f;
  EXPECT_NEAR(m.shape[north].y, 350.0f + 250.0f * (0.6f + 0.4f * std::sqrt(1.0f - f * f)), 1.0f);
  for (size_t k = 0; k < m.shape.size(); ++k)
    if (m.shape[k].z > 0.0f) {
      EXPECT_LE(m.shape[k].y, ceiling(centre(m, k).x, centre(m, k).y) - kCeilingGapM) << k;
    }
}

TEST(EnvelopeBake, PaintedMapsSetTheHeights) {
  test::TempDir tmp(test::test_temp_name("cumulo_envelope_paint"));
  const uint32_t w = 20, h = 10;
  std::vector<uint8_t> bottom(w * h, 51), coverage(w * h, 0);  // 0.2 -> 160 m
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w / 2; ++x) coverage[y * w + x] = 255;  // the western half
  write_png(tmp.path / "bottom.png", bottom.data(), w, h, 1);
  write_png(tmp.path / "coverage.png", coverage.data(), w, h, 1);
  test::write_grey_png16(tmp.path / "top.png", std::vector<uint16_t>(w * h, 49151), w, h);  // 0.75 -> 600 m
  OrographicClouds spec;
  spec.extent_min = glm::vec2(0.0f, 0.0f);
  spec.extent_max = glm::vec2(400.0f, 200.0f);  // the map's square reaches z = 400
  spec.resolution = 40;
  PaintedMapSet set;
  set.bottom = {"bottom.png", "$.maps.bottom"};
  set.top = {"top.png", "$.maps.top"};
  set.coverage = {"coverage.png", "$.maps.coverage"};
  set.height_range = glm::vec2(0.0f, 800.0f);
  spec.maps = set;
  resolve_orographic_clouds(spec, tmp.path);
  auto flat = [](float, float) { return 100.0f; };
  const EnvelopeMaps m = bake_envelope_maps(spec, flat);
  const glm::vec4 west = m.shape[texel_at(m, glm::vec2(50.0f, 100.0f))];
  EXPECT_NEAR(west.x, 160.0f, 1e-3f);
  EXPECT_NEAR(west.y, 800.0f * 49151.0f / 65535.0f, 1e-3f);  // 16 bits: 599.99, not 8 bits' 602.35
  EXPECT_FLOAT_EQ(west.z, 1.0f);
  EXPECT_FLOAT_EQ(west.w, 0.5f);
  EXPECT_EQ(m.shape[texel_at(m, glm::vec2(350.0f, 100.0f))].z, 0.0f);
  EXPECT_EQ(m.shape[texel_at(m, glm::vec2(50.0f, 300.0f))].z, 0.0f);  // past the extent

  // Relative to the ground, and read by the bake itself when nothing resolved them.
  spec.maps->relative_to_terrain = true;
  spec.painted.reset();
  const EnvelopeMaps ground = bake_envelope_maps(spec, flat);
  EXPECT_NEAR(ground.shape[texel_at(ground, glm::vec2(50.0f, 100.0f))].x, 260.0f, 1e-3f);
  spec.level_dir = tmp.path / "elsewhere";
  try {
    bake_envelope_maps(spec, flat);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("$.maps.bottom"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bottom.png"), std::string::npos) << e.what();
  }
}

// The CPU density query agrees with the profile at texel centres, and wherever it finds density the texel's
// conservative top and bottom enclose it.
TEST(EnvelopeBake, SampleAgreesWithTheStepData) {
  EnvelopeRule bank;
  bank.kind = BankRule{glm::vec3(-1.0f, 0.0f, -0.3f), glm::vec2(20.0f, 260.0f), 40.0f, 220.0f};
  EnvelopeRule layer;
  layer.kind = LayerRule{60.0f, 0.0f, 80.0f};
  OrographicClouds spec = spec_with({cap_at_peak(350.0f, 380.0f, 620.0f), bank, layer}, 96);
  spec.edge_m = 35.0f;
  const EnvelopeMaps m = bake_envelope_maps(spec, gaussian_terrain);
  EXPECT_FLOAT_EQ(m.edge_width_m, 35.0f);
  for (size_t k = 0; k < m.shape.size(); k += 7) {
    const glm::vec2 c = centre(m, k);
    const glm::vec4 s = m.shape[k];
    const float y = glm::mix(s.x, s.y, 0.4f);
    const EnvelopeSample e = sample_envelope(m, glm::vec3(c.x, y, c.y));
    EXPECT_NEAR(e.shape.x, s.x, 1e-3f);
    EXPECT_NEAR(e.shape.z, s.z, 1e-5f);
    EXPECT_NEAR(e.edge_m, m.edge_m[k], 1e-3f);
    EXPECT_NEAR(e.profile, envelope_profile(y, s.x, s.y, m.edge_m[k], 35.0f, s.z), 1e-4f);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int dense = 0;
  for (int i = 0; i < 200000; ++i) {
    const glm::vec3 p(-1000.0f + 2000.0f * u(rng), 700.0f * u(rng), -1000.0f + 2000.0f * u(rng));
    if (sample_envelope(m, p).profile <= 0.0f) continue;
    ++dense;
    const glm::vec4 s = m.steps[texel_at(m, glm::vec2(p.x, p.z))];
    ASSERT_LT(p.y, s.x);
    ASSERT_GT(p.y, s.y);
    ASSERT_EQ(m.distance_m[texel_at(m, glm::vec2(p.x, p.z))], 0.0f);
  }
  EXPECT_GT(dense, 1000);
  EXPECT_EQ(sample_envelope(m, glm::vec3(-1200.0f, 30.0f, -900.0f)).profile, 0.0f);  // outside the map
}

// Resolution 256 with every rule, on one thread: well under 2 s in an optimised build.
TEST(EnvelopeBake, Resolution256BakesQuicklyOnOneThread) {
  EnvelopeRule bank;
  bank.kind = BankRule{glm::vec3(-1.0f, 0.0f, -0.3f), glm::vec2(20.0f, 260.0f), 40.0f, 220.0f};
  bank.region = EnvelopeRegion{glm::vec2(-29.0f, 267.0f), 900.0f};
  EnvelopeRule layer;
  layer.kind = LayerRule{60.0f, 0.0f, 80.0f};
  const OrographicClouds spec = spec_with({cap_at_peak(350.0f, 180.0f, 520.0f), bank, layer}, 256);
  ::setenv("CUMULO_THREADS", "1", 1);
  const auto start = std::chrono::steady_clock::now();
  const EnvelopeMaps m = bake_envelope_maps(spec, gaussian_terrain);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ::unsetenv("CUMULO_THREADS");
  std::printf("resolution 256 on one thread: %.3f s\n", s);
  RecordProperty("bake_s", std::to_string(s));
  EXPECT_EQ(m.shape.size(), 256u * 256u);
#ifdef NDEBUG
  EXPECT_LT(s, 2.0);
#endif
}
