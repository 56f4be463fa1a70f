// In-memory Volume: sizes, texel encode/decode per encoding, decode ranges, mips, block decoders.
#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {
namespace {

TEST(Volume, LevelSizesAndBytes) {
  EXPECT_EQ(mip_level_size({512, 512, 64}, 0), glm::uvec3(512, 512, 64));
  EXPECT_EQ(mip_level_size({512, 512, 64}, 7), glm::uvec3(4, 4, 1));
  EXPECT_EQ(mip_level_size({512, 512, 64}, 9), glm::uvec3(1, 1, 1));
  EXPECT_EQ(full_mip_count({512, 512, 64}), 10u);
  EXPECT_EQ(full_mip_count({1, 1, 1}), 1u);
  EXPECT_EQ(full_mip_count({128, 128, 128}), 8u);
  // The talk's figures: modeling 512x512x64 at 1 B/texel = 16.777 MB; BC1 field at 0.5 B/texel.
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::R8, {512, 512, 64}), 16777216u);
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::BC1, {512, 512, 64}), 8388608u);
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::R4G4B4A4, {128, 128, 128}), 4194304u);  // talk: 4.194 MB
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::BC1, {5, 5, 2}), 2u * 2u * 2u * 8u);  // partial blocks
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::BC7, {4, 4, 1}), 16u);
  // Overflow-safe: absurd sizes report UINT64_MAX rather than wrapping.
  EXPECT_EQ(encoded_level_bytes(VolumeEncoding::RGBA16, {0xffffffffu, 0xffffffffu, 0xffffffffu}), UINT64_MAX);
}

TEST(Volume, EncodingNames) {
  for (uint32_t e = 1; e <= 10; ++e) {
    ASSERT_TRUE(is_valid_encoding(e));
    VolumeEncoding parsed;
    ASSERT_TRUE(parse_encoding(encoding_name(static_cast<VolumeEncoding>(e)), &parsed));
    EXPECT_EQ(static_cast<uint32_t>(parsed), e);
  }
  EXPECT_FALSE(is_valid_encoding(0));
  EXPECT_FALSE(is_valid_encoding(11));
}

TEST(Volume, TexelRoundtripPerEncoding) {
  struct Case {
    VolumeEncoding e;
    float step;  // quantisation step
  } cases[] = {{VolumeEncoding::R8, 1 / 255.0f},     {VolumeEncoding::RG8, 1 / 255.0f},
               {VolumeEncoding::RGBA8, 1 / 255.0f},  {VolumeEncoding::R16, 1 / 65535.0f},
               {VolumeEncoding::RGBA16, 1 / 65535.0f}, {VolumeEncoding::R32F, 0.0f},
               {VolumeEncoding::R4G4B4A4, 1 / 15.0f}};
  for (const Case& k : cases) {
    SCOPED_TRACE(encoding_name(k.e));
    Volume v = Volume::create({5, 4, 3}, 2.0f, k.e, {{"a", "x"}});
    const uint32_t comps = encoding_components(k.e);
    for (uint32_t z = 0; z < 3; ++z)
      for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 5; ++x)
          for (uint32_t c = 0; c < comps; ++c) v.set_texel(x, y, z, c, float((x + 2 * y + 3 * z + c) % 11) / 10.0f);
    for (uint32_t z = 0; z < 3; ++z)
      for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 5; ++x)
          for (uint32_t c = 0; c < comps; ++c)
            EXPECT_NEAR(v.texel(x, y, z, c), float((x + 2 * y + 3 * z + c) % 11) / 10.0f, k.step * 0.5f + 1e-6f);
  }
}

TEST(Volume, UnormClampsAndRounds) {
  Volume v = Volume::create({2, 1, 1}, 1.0f, VolumeEncoding::R8, {{"a", "x"}});
  v.set_texel(0, 0, 0, 0, 1.7f);
  v.set_texel(1, 0, 0, 0, -3.0f);
  EXPECT_EQ(v.levels[0][0], 255);
  EXPECT_EQ(v.levels[0][1], 0);
  v.set_texel(0, 0, 0, 0, std::nanf(""));
  EXPECT_EQ(v.levels[0][0], 0);
}

TEST(Volume, R4G4B4A4FollowsVulkanPackOrder) {
  Volume v = Volume::create({1, 1, 1}, 1.0f, VolumeEncoding::R4G4B4A4, {{"a", "x"}});
  v.set_texel(0, 0, 0, 0, 1.0f);  // R -> bits 12..15
  v.set_texel(0, 0, 0, 3, 2.0f / 15.0f);  // A -> bits 0..3
  EXPECT_EQ(v.levels[0][0] | (v.levels[0][1] << 8), 0xf002);
}

TEST(Volume, DecodeRangeForSdf) {
  Volume f = make_field_volume({4, 4, 2}, 8.0f, {0, 0, 0});
  const uint32_t c = f.channel(kSignedDistance, "test");
  f.set_decoded(1, 2, 1, c, -256.0f);
  f.set_decoded(2, 2, 1, c, 0.0f);
  f.set_decoded(3, 2, 1, c, 4096.0f);
  EXPECT_FLOAT_EQ(f.texel(1, 2, 1, c), 0.0f);
  EXPECT_FLOAT_EQ(f.texel(3, 2, 1, c), 1.0f);
  EXPECT_NEAR(f.decoded(2, 2, 1, c), 0.0f, 4352.0f / 65535.0f);
  EXPECT_EQ(f.bounds_max, glm::vec3(32, 32, 16));
}

TEST(Volume, ChannelLookupNamesWhatIsMissing) {
  Volume m = make_modeling_volume({2, 2, 2}, 8.0f, {0, 0, 0});
  check_modeling_volume(m, "m.nvdf");
  try {
    check_field_volume(m, "m.nvdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "m.nvdf: no channel with semantic 'sdf' (has: dimensional_profile, detail_type, density_scale, coverage_threshold)");
  }
}

TEST(Volume, MipsAverageBoxes) {
  Volume v = Volume::create({4, 2, 2}, 1.0f, VolumeEncoding::R32F, {{"a", "x"}});
  for (uint32_t z = 0; z < 2; ++z)
    for (uint32_t y = 0; y < 2; ++y)
      for (uint32_t x = 0; x < 4; ++x) v.set_texel(x, y, z, 0, float(x));
  generate_mips(v);
  ASSERT_EQ(v.mip_count(), 3u);
  EXPECT_EQ(v.level_size(1), glm::uvec3(2, 1, 1));
  EXPECT_FLOAT_EQ(v.texel(0, 0, 0, 0, 1), 0.5f);
  EXPECT_FLOAT_EQ(v.texel(1, 0, 0, 0, 1), 2.5f);
  EXPECT_FLOAT_EQ(v.texel(0, 0, 0, 0, 2), 1.5f);
  v.validate("mips");
}

TEST(Volume, MipsOfOddSizeWrapOrClamp) {
  Volume v = Volume::create({3, 1, 1}, 1.0f, VolumeEncoding::R32F, {{"a", "x"}});
  v.set_texel(0, 0, 0, 0, 1.0f);
  v.set_texel(1, 0, 0, 0, 2.0f);
  v.set_texel(2, 0, 0, 0, 4.0f);
  generate_mips(v, 2, false);
  EXPECT_FLOAT_EQ(v.texel(0, 0, 0, 0, 1), 1.5f);
  EXPECT_THROW(v.texel(1, 0, 0, 0, 1), Error);  // level 1 is 1 texel wide
  Volume b = Volume::create({4, 4, 1}, 1.0f, VolumeEncoding::BC1, {{"a", "x"}});
  EXPECT_THROW(generate_mips(b), Error);
}

TEST(Volume, Bc1ReferenceDecode) {
  Volume v = Volume::create({4, 4, 1}, 1.0f, VolumeEncoding::BC1, {{"a", "sdf"}});
  uint8_t* b = v.levels[0].data();
  // c0 = white (0xffff) > c1 = black (0x0000): 4-colour mode.
  b[0] = 0xff, b[1] = 0xff, b[2] = 0x00, b[3] = 0x00;
  b[4] = 0b11100100;  // row 0: indices 0,1,2,3
  EXPECT_FLOAT_EQ(v.texel(0, 0, 0, 0), 1.0f);
  EXPECT_FLOAT_EQ(v.texel(1, 0, 0, 1), 0.0f);
  EXPECT_FLOAT_EQ(v.texel(2, 0, 0, 2), 2.0f / 3.0f);
  EXPECT_FLOAT_EQ(v.texel(3, 0, 0, 0), 1.0f / 3.0f);
  // Swapped endpoints: 3-colour mode, index 3 is transparent black.
  b[0] = 0x00, b[1] = 0x00, b[2] = 0xff, b[3] = 0xff;
  EXPECT_FLOAT_EQ(v.texel(2, 0, 0, 0), 0.5f);
  EXPECT_FLOAT_EQ(v.texel(3, 0, 0, 3), 0.0f);
  // Red 565 endpoint 16 expands by bit replication to (16 << 3 | 16 >> 2) = 132.
  b[0] = 0x00, b[1] = 0x80, b[2] = 0x00, b[3] = 0x00, b[4] = 0;
  EXPECT_FLOAT_EQ(v.texel(0, 0, 0, 0), 132.0f / 255.0f);
}

TEST(Volume, Bc4ReferenceDecode) {
  uint8_t block[8] = {255, 0, 0, 0, 0, 0, 0, 0};
  // texel 1 index 2 -> (6*r0 + 1*r1)/7
  block[2] = 2 << 3;
  EXPECT_FLOAT_EQ(bc4_decode_texel(block, 0, 0), 1.0f);
  EXPECT_FLOAT_EQ(bc4_decode_texel(block, 1, 0), 6.0f / 7.0f);
  block[0] = 0, block[1] = 255;  // 6-value mode; index 7 -> 1, index 6 -> 0
  block[2] = 7 << 3 | 6;
  EXPECT_FLOAT_EQ(bc4_decode_texel(block, 0, 0), 0.0f);
  EXPECT_FLOAT_EQ(bc4_decode_texel(block, 1, 0), 1.0f);
}

TEST(Volume, ValidateNamesTheProblem) {
  Volume v = make_modeling_volume({2, 2, 2}, 8.0f, {0, 0, 0});
  v.bounds_max.z = -1.0f;
  try {
    v.validate("x.nvdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.nvdf: world bounds axis z"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cumulo::clouds
