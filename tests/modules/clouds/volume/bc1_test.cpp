// The conservative BC1 SDF: exact decode, the talk's unpack constants, and the never-above bound
// under every decoder model, texel by texel and at filtered midpoints.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "modules/clouds/volume/bc1.h"
#include "modules/clouds/volume/volume.h"

using namespace cumulo::clouds;

TEST(Bc1Sdf, UnpackConstantsAreTheTalksFromTheExactExpansion) {
  // 2023 talk: dot(rgb, float3(1.0, 0.03529415, 0.00069204)).
  EXPECT_NEAR(kSdfDotG, 0.03529415, 5e-8);
  EXPECT_NEAR(kSdfDotB, 0.00069204, 5e-9);
  // G's full range covers the largest step between bit-replicated 5-bit R levels...
  int max_r_step = 0, max_g_step = 0;
  for (int k = 0; k < 31; ++k) {
    glm::ivec3 a = bc1_expand(uint16_t(k << 11)), b = bc1_expand(uint16_t((k + 1) << 11));
    max_r_step = std::max(max_r_step, b.x - a.x);
  }
  for (int k = 0; k < 63; ++k) {
    glm::ivec3 a = bc1_expand(uint16_t(k << 5)), b = bc1_expand(uint16_t((k + 1) << 5));
    max_g_step = std::max(max_g_step, b.y - a.y);
  }
  EXPECT_EQ(max_r_step, 9);
  EXPECT_EQ(max_g_step, 5);
  EXPECT_DOUBLE_EQ(kSdfDotG, max_r_step / 255.0);
  EXPECT_DOUBLE_EQ(kSdfDotB, kSdfDotG * max_g_step / 255.0);
}

TEST(Bc1Sdf, EndpointRoundDownIsBelowAndClose) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    double v = i < 65536 ? i / 65535.0 : u(rng);
    double dec = sdf_unpack(glm::dvec3(bc1_expand(sdf_endpoint_round_down(v))) / 255.0);
    ASSERT_LE(dec, v) << v;
    worst = std::max(worst, v - dec);
  }
  // The B channel's largest step (9/255 of its weight) bounds the residual: ~16 bits.
  EXPECT_LE(worst, 9.0 / 255.0 * kSdfDotB + 1e-12);
  EXPECT_LT(worst * 4352.0, 0.11);  // metres
}

TEST(Bc1Decode, VolumeTexelIsTheExactModelWithAlpha) {
  // Volume::texel() decodes BC1 through the one decoder: RGB from the Exact model, alpha 0 only for
  // the black entry of the three-colour mode.
  std::mt19937 rng(9);
  Volume v = Volume::create({4, 4, 1}, 1.0f, VolumeEncoding::BC1, {{"a", "x"}});
  for (int i = 0; i < 2000; ++i) {
    for (auto& b : v.levels[0]) b = uint8_t(rng());
    const uint8_t* block = v.levels[0].data();
    const bool three_colour = (block[0] | (block[1] << 8)) <= (block[2] | (block[3] << 8));
    for (uint32_t t = 0; t < 16; ++t) {
      const glm::dvec3 a = bc1_decode_texel_model(block, t % 4, t / 4, Bc1Model::Exact);
      for (uint32_t c = 0; c < 3; ++c) ASSERT_EQ(v.texel(t % 4, t / 4, 0, c), float(a[c]));
      const uint32_t index = (v.levels[0][4 + t / 4] >> (2 * (t % 4))) & 3u;
      ASSERT_EQ(v.texel(t % 4, t / 4, 0, 3), three_colour && index == 3 ? 0.0f : 1.0f);
    }
  }
  // Models differ only in the interpolated entries, and by at most about one 8-bit step.
  uint8_t block[8] = {0x00, 0xF8, 0x00, 0x00, 0xAA, 0xAA, 0xAA, 0xAA};  // c0 = red, c1 = black, all index 2
  for (Bc1Model m : kBc1Models) EXPECT_NEAR(bc1_decode_texel_model(block, 0, 0, m).x, 170.0 / 255.0, 1.01 / 255.0);
  // The three-colour mode (c0 <= c1): index 2 is the midpoint, index 3 transparent black.
  uint8_t three[8] = {0x00, 0x00, 0x00, 0xF8, 0x0E, 0, 0, 0};  // c0 = black, c1 = red; texels 0..1: index 2, 3
  EXPECT_EQ(bc1_decode_texel(three, 0, 0), glm::vec4(0.5f, 0.0f, 0.0f, 1.0f));
  EXPECT_EQ(bc1_decode_texel(three, 1, 0), glm::vec4(0.0f));
}

namespace {

// A smooth random field in metres: a few Gaussian blobs' distance-like bumps plus gentle waves.
std::vector<uint16_t> smooth_field(glm::uvec3 d, uint32_t seed, std::vector<float>* metres) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  struct Blob { glm::vec3 c; float r; };
  std::vector<Blob> blobs;
  for (int i = 0; i < 5; ++i) blobs.push_back({{u(rng) * d.x * 8, u(rng) * d.y * 8, u(rng) * d.z * 8}, 20 + 60 * u(rng)});
  float fx = 0.01f + 0.05f * u(rng), fz = 0.01f + 0.05f * u(rng);
  std::vector<uint16_t> q(size_t(d.x) * d.y * d.z);
  metres->resize(q.size());
  for (uint32_t z = 0; z < d.z; ++z)
    for (uint32_t y = 0; y < d.y; ++y)
      for (uint32_t x = 0; x < d.x; ++x) {
        glm::vec3 p = glm::vec3(x, y, z) * 8.0f;
        float m = 1e9f;
        for (auto& b : blobs) m = std::min(m, glm::length(p - b.c) - b.r);
        m += 6.0f * std::sin(p.x * fx) * std::cos(p.z * fz);
        m = std::clamp(m, -256.0f, 4096.0f);
        size_t i = x + d.x * (y + size_t(d.y) * z);
        (*metres)[i] = m;
        q[i] = uint16_t((m + 256.0) / 4352.0 * 65535.0);
      }
  return q;
}

}  // namespace

TEST(Bc1Sdf, ConservativeOnRandomSmoothFieldsExhaustively) {
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    glm::uvec3 d(30 + seed, 13 + seed, 5);  // partial blocks on purpose
    std::vector<float> metres;
    std::vector<uint16_t> q = smooth_field(d, seed, &metres);
    std::vector<uint8_t> blocks = encode_sdf_bc1(q, d);
    ASSERT_EQ(blocks.size(), size_t((d.x + 3) / 4) * ((d.y + 3) / 4) * d.z * 8);
    // Independent check: every texel, every decoder model.
    const uint32_t bx = (d.x + 3) / 4, by = (d.y + 3) / 4;
    for (uint32_t z = 0; z < d.z; ++z)
      for (uint32_t y = 0; y < d.y; ++y)
        for (uint32_t x = 0; x < d.x; ++x) {
          const uint8_t* blk = &blocks[((size_t(z) * by + y / 4) * bx + x / 4) * 8];
          double v = q[x + d.x * (y + size_t(d.y) * z)] / 65535.0;
          for (Bc1Model m : kBc1Models) ASSERT_LE(sdf_unpack(bc1_decode_texel_model(blk, x % 4, y % 4, m)), v);
        }
    Bc1SdfReport r = verify_sdf_bc1(blocks, q, d, &metres);
    EXPECT_EQ(r.violations, 0u);
    EXPECT_EQ(r.midpoint_violations, 0u);
    EXPECT_GT(r.midpoint_checks, 3u * r.texels / 2);
    EXPECT_GE(r.mean_error_m, 0.0);
    // Smooth data keeps most of the 16 bits: well under a voxel on average.
    EXPECT_LT(r.mean_error_m, 4.0) << "seed " << seed;
    EXPECT_GE(r.mean_error_vs_float_m, r.mean_error_m);
  }
}

TEST(Bc1Sdf, ConservativeEvenOnNoise) {
  // The bound must hold for any input, not only smooth ones.
  glm::uvec3 d(16, 16, 3);
  std::mt19937 rng(11);
  std::vector<uint16_t> q(size_t(d.x) * d.y * d.z);
  for (auto& v : q) v = uint16_t(rng());
  q[0] = 0, q[1] = 65535;
  std::vector<uint8_t> blocks = encode_sdf_bc1(q, d);
  Bc1SdfReport r = verify_sdf_bc1(blocks, q, d);
  EXPECT_EQ(r.violations, 0u);
  EXPECT_EQ(r.midpoint_violations, 0u);
}

TEST(Bc1Rgb, ModelingEncoderIsAccurateOnSmoothData) {
  glm::uvec3 d(32, 16, 2);
  std::vector<float> rgb(size_t(d.x) * d.y * d.z * 3);
  for (uint32_t z = 0; z < d.z; ++z)
    for (uint32_t y = 0; y < d.y; ++y)
      for (uint32_t x = 0; x < d.x; ++x) {
        size_t i = x + d.x * (y + size_t(d.y) * z);
        rgb[3 * i] = std::clamp((x + y) / 40.0f, 0.0f, 1.0f);
        rgb[3 * i + 1] = x < 16 ? 0.2f : 0.9f;
        rgb[3 * i + 2] = 0.75f;
      }
  auto blocks = encode_rgb_bc1(rgb, d, {2, 1, 1});
  Bc1RgbReport r = measure_rgb_bc1(blocks, rgb, d);
  EXPECT_LT(r.rmse.x, 0.02);
  EXPECT_LT(r.rmse.y, 0.02);
  EXPECT_LT(r.rmse.z, 0.02);
}
