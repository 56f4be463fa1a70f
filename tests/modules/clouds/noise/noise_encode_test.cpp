// Storage of the noise: 4-bit packing, the Volume/.nvdf form, the quality measurements, the up-rez
// function, and `cumulo noise` end to end at a small size.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>


#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

TEST(NoiseEncode, R4G4B4A4PackingRoundtripAndBitOrder) {
  EXPECT_EQ(pack_r4g4b4a4(1, 0, 0, 0), 0xF000);
  EXPECT_EQ(pack_r4g4b4a4(0, 1, 0, 0), 0x0F00);
  EXPECT_EQ(pack_r4g4b4a4(0, 0, 1, 0), 0x00F0);
  EXPECT_EQ(pack_r4g4b4a4(0, 0, 0, 1), 0x000F);
  EXPECT_EQ(pack_r4g4b4a4(-3, 2, 0.5f, 0), 0x0F80);  // clamped; 0.5 * 15 = 7.5 rounds to 8
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float worst = 0;
  for (int i = 0; i < 20000; ++i) {
    float v[4] = {u(rng), u(rng), u(rng), u(rng)};
    uint16_t w = pack_r4g4b4a4(v[0], v[1], v[2], v[3]);
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(unpack_r4g4b4a4(w, c) - v[c]));
  }
  EXPECT_LE(worst, 1.0f / 30.0f + 1e-6f);
  EXPECT_GT(worst, 1.0f / 30.0f - 1e-3f);  // and the bound is tight: 4 bits, not more
}

NoiseTexture small_voxel_noise() {
  VoxelNoiseParams p;
  p.size = 16;
  p.seed = 3;
  return generate_voxel_noise(p);
}

const std::vector<NoiseChannelInfo> kFour = {{"r"}, {"g"}, {"b"}, {"a"}};

TEST(NoiseEncode, VolumeHoldsEveryMipWithinHalfAStep) {
  NoiseTexture t = small_voxel_noise();
  for (auto [enc, step] : {std::pair{VolumeEncoding::R4G4B4A4, 15.0f}, std::pair{VolumeEncoding::RGBA8, 255.0f}}) {
    Volume v = noise_to_volume(t, enc, kFour);
    ASSERT_EQ(v.mip_count(), static_cast<uint32_t>(t.levels()));
    EXPECT_EQ(v.level_bytes(0), 16u * 16 * 16 * (enc == VolumeEncoding::R4G4B4A4 ? 2 : 4));
    EXPECT_NEAR(v.voxel_size, 100.0f / 16.0f, 1e-6f);
    for (int level = 0; level < t.levels(); ++level) {
      float worst = 0;
      for (int z = 0; z < t.level_depth(level); ++z)
        for (int y = 0; y < t.level_height(level); ++y)
          for (int x = 0; x < t.level_width(level); ++x)
            for (int c = 0; c < 4; ++c)
              worst = std::max(worst, std::abs(v.texel(x, y, z, c, level) - t.at(level, x, y, z, c)));
      EXPECT_LE(worst, 0.5f / step + 1e-6f) << encoding_name(enc) << " level " << level;
    }
  }
  EXPECT_THROW(noise_to_volume(t, VolumeEncoding::RGBA8, {{"r"}}), Error);  // channel count mismatch
  EXPECT_THROW(noise_to_volume(t, VolumeEncoding::R8, kFour), Error);       // 4 channels do not fit
}

TEST(NoiseEncode, QualityMeasurementsOrderTheFormats) {
  NoiseTexture t = small_voxel_noise();
  auto e4 = quantization_error(t, VolumeEncoding::R4G4B4A4);
  auto e8 = quantization_error(t, VolumeEncoding::RGBA8);
  ASSERT_EQ(e4.size(), 4u);
  for (int c = 0; c < 4; ++c) {
    EXPECT_LE(e4[c].max_abs, 1.0 / 30.0 + 1e-6);
    EXPECT_LE(e8[c].max_abs, 1.0 / 510.0 + 1e-6);
    EXPECT_GT(e4[c].psnr_db, 30.0);  // uniform error of a 1/15 step: ~34.8 dB
    EXPECT_GT(e8[c].psnr_db, e4[c].psnr_db + 20.0);
  }
  UprezError u4 = uprez_error(t, VolumeEncoding::R4G4B4A4), u8 = uprez_error(t, VolumeEncoding::RGBA8);
  UprezError uf = uprez_error(t, VolumeEncoding::R32F);
  EXPECT_EQ(uf.max_abs, 0.0);
  EXPECT_GT(u4.mean_abs, u8.mean_abs);
  EXPECT_GT(u4.mean_density, 0.05);
  EXPECT_EQ(u4.mean_density, u8.mean_density);
}

TEST(NoiseEncode, UprezDensityFollowsTheTalk) {
  const float noise[4] = {0.6f, 0.4f, 0.8f, 0.2f};
  EXPECT_EQ(uprez_density(noise, 0.0f, 0.5f, 1.0f), 0.0f);  // outside the cloud
  // Denser inside: the dimensional profile is eroded, not replaced.
  float prev = 0;
  for (int i = 1; i <= 10; ++i) {
    float d = uprez_density(noise, 0.1f * static_cast<float>(i), 1.0f, 1.0f);
    EXPECT_GE(d, prev);
    prev = d;
  }
  EXPECT_NEAR(prev, 1.0f, 1e-5f);  // profile 1 survives any erosion < 1
  EXPECT_EQ(uprez_density(noise, 0.5f, 0.5f, 0.0f), 0.0f);
  // Hand-evaluated: profile 0.5, type 1 (billowy): billowy = lerp(0.24, 0.06, 0.5^0.25 = 0.8409) = 0.0886;
  // erosion (0.5 - 0.0886) / (1 - 0.0886) = 0.4514; density scale 1 -> exponent 0.6.
  EXPECT_NEAR(uprez_density(noise, 0.5f, 1.0f, 1.0f), std::pow(0.45138f, 0.6f), 1e-4f);
  EXPECT_EQ(value_erosion(0.3f, 1.0f), 0.0f);
  EXPECT_FLOAT_EQ(value_erosion(0.3f, 0.0f), 0.3f);
}

TEST(NoiseCommand, WritesLoadableVolumesAndPreviews) {
  fs::path dir = cumulo::test::fresh_temp_dir("cumulo_noise_test_cmd");
  NoiseSetOptions o;
  o.out_dir = dir;
  o.size = 16;
  o.seed = 5;
  o.format = NoiseFormat::Both;
  o.progress = false;
  NoiseSetReport r = write_noise_set(o);
  ASSERT_EQ(r.files.size(), 6u);
  ASSERT_EQ(r.voxel_quality.size(), 2u);
  for (const char* name : {"voxel_noise.nvdf", "voxel_noise_r4g4b4a4.nvdf", "voxel_noise_rgba8.nvdf",
                           "sky_noise_base.nvdf", "sky_noise_detail.nvdf", "curl_noise.nvdf",
                           "voxel_noise_preview.png", "curl_noise_preview.png"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  Volume voxel = load_volume(dir / "voxel_noise.nvdf");
  EXPECT_EQ(voxel.encoding, kVoxelNoiseEncoding);
  EXPECT_EQ(voxel.size, glm::uvec3(16));
  EXPECT_EQ(voxel.mip_count(), 5u);
  ASSERT_EQ(voxel.channels.size(), 4u);
  EXPECT_EQ(voxel.channels[0].name, "curly_alligator_low");
  EXPECT_EQ(voxel.channels[3].semantic, "noise");
  EXPECT_EQ(load_volume(dir / "voxel_noise_rgba8.nvdf").encoding, VolumeEncoding::RGBA8);
  Volume detail = load_volume(dir / "sky_noise_detail.nvdf");
  EXPECT_EQ(detail.size, glm::uvec3(4));
  EXPECT_EQ(detail.channels.size(), 3u);
  Volume curl = load_volume(dir / "curl_noise.nvdf");
  EXPECT_EQ(curl.size, glm::uvec3(16, 16, 1));
  EXPECT_LT(curl.channels[0].decode_min, 0.0f);
  EXPECT_EQ(curl.channels[0].decode_max, -curl.channels[0].decode_min);
  EXPECT_NE(format_noise_report(r).find("voxel_noise.nvdf"), std::string::npos);

  // Same seed, same bytes.
  fs::path dir2 = cumulo::test::fresh_temp_dir("cumulo_noise_test_cmd2");
  o.out_dir = dir2;
  o.measure = false;
  o.previews = false;
  write_noise_set(o);
  for (const char* name : {"voxel_noise.nvdf", "sky_noise_base.nvdf", "sky_noise_detail.nvdf", "curl_noise.nvdf"})
    EXPECT_EQ(read_file_bytes(dir / name), read_file_bytes(dir2 / name)) << name;
  fs::remove_all(dir);
  fs::remove_all(dir2);
}

TEST(NoiseCommand, RejectsBadArguments) {
  CommandRegistry reg;
  register_noise_command(reg);
  const Command* cmd = reg.find("noise");
  ASSERT_NE(cmd, nullptr);
  auto run = [&](std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    return cmd->run(static_cast<int>(argv.size()), argv.data());
  };
  EXPECT_THROW(run({"noise"}), Error);                                        // no -o
  EXPECT_THROW(run({"noise", "-o", "/tmp/x", "--format", "5"}), Error);       // bad format
  EXPECT_THROW(run({"noise", "-o", "/tmp/x", "--size", "100"}), Error);       // not a power of two
  EXPECT_THROW(run({"noise", "-o", "/dev/null/sub", "--size", "4"}), Error);  // cannot create
}

}  // namespace
}  // namespace cumulo::clouds
