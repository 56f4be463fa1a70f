// Cloud assets on the GPU (lavapipe, validation on): both format sets load from a baked folder, one
// GPU copy per canonical path, and every bad or missing file is refused with its name.
#include <gtest/gtest.h>

#include <fstream>

#include "engine/core/error.h"
#include "engine/gpu/readback.h"
#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/render/cloud_render_options.h"
#include "modules/clouds/volume/nvdf.h"
#include "tests/modules/clouds/render/cloud_test_util.h"

using namespace cumulo;
using namespace cumulo::clouds;
using namespace cumulo::clouds::render;
using cumulo::clouds::render::test::test_data;

namespace {

namespace fs = std::filesystem;

class CloudAssets : public gpu::test::GpuTest {};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

fs::path copy_folder(const fs::path& from, const std::string& name) {
  const fs::path to = test_data().root / name;
  fs::remove_all(to);
  fs::create_directories(to);
  for (const auto& e : fs::directory_iterator(from)) fs::copy_file(e.path(), to / e.path().filename());
  return to;
}

}  // namespace

TEST_F(CloudAssets, BothFormatSetsLoadWithTheBakedBoxAndFormats) {
  const auto& data = test_data();
  std::shared_ptr<CloudAsset> u = load_cloud_asset(ctx(), data.cloudscape, CloudFormats::from_set(CloudFormatSet::Uncompressed));
  EXPECT_EQ(u->dims, glm::uvec3(64, 32, 64));
  EXPECT_EQ(u->modeling.format(), VK_FORMAT_R8G8B8A8_UNORM);
  EXPECT_EQ(u->field.format(), VK_FORMAT_R16_UNORM);
  EXPECT_EQ(u->bounds_min, glm::vec3(-256, 0, -256));
  EXPECT_EQ(u->bounds_max, glm::vec3(256, 256, 256));
  EXPECT_EQ(u->gpu_bytes, 64u * 32 * 64 * (4 + 2));
  EXPECT_EQ(u->modeling.layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  if (!ctx().info().texture_compression_bc) GTEST_SKIP() << "no BC texture support";
  std::shared_ptr<CloudAsset> c = load_cloud_asset(ctx(), data.cloudscape, CloudFormats::from_set(CloudFormatSet::Compressed));
  EXPECT_EQ(c->modeling.format(), VK_FORMAT_BC1_RGB_UNORM_BLOCK);
  EXPECT_EQ(c->field.format(), VK_FORMAT_BC1_RGB_UNORM_BLOCK);
  EXPECT_EQ(c->coverage.format(), VK_FORMAT_R8_UNORM);
  EXPECT_EQ(c->coverage.extent().width, 32u);  // half resolution per axis
  EXPECT_EQ(c->coverage.extent().height, 16u);
  EXPECT_EQ(c->gpu_bytes, 64u * 32 * 64 / 2 * 2 + 32u * 16 * 32);  // 0.5 byte per texel each + the R8 coverage
  // The GPU holds the file's bytes: read the BC1 field back and compare with the file.
  Volume f = load_volume(data.cloudscape / kFieldBc1FileName);
  EXPECT_EQ(gpu::read_image_bytes(ctx(), c->field), f.levels[0]);
}

TEST_F(CloudAssets, DefaultFormatSetFollowsTheDeviceType) {
  gpu::DeviceInfo cpu;
  cpu.type = VK_PHYSICAL_DEVICE_TYPE_CPU;
  cpu.texture_compression_bc = true;
  EXPECT_EQ(default_format_set(cpu), CloudFormatSet::Uncompressed);
  gpu::DeviceInfo gpu_info;
  gpu_info.type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  gpu_info.texture_compression_bc = true;
  EXPECT_EQ(default_format_set(gpu_info), CloudFormatSet::Compressed);
  gpu_info.texture_compression_bc = false;
  EXPECT_EQ(default_format_set(gpu_info), CloudFormatSet::Uncompressed);
  EXPECT_EQ(parse_name(kCloudFormatSetNames, "compressed"), CloudFormatSet::Compressed);
  EXPECT_FALSE(parse_name(kCloudFormatSetNames, "bc6h"));
  if (ctx().info().is_cpu()) {
    EXPECT_EQ(default_format_set(ctx().info()), CloudFormatSet::Uncompressed);
  }
}

TEST(CloudSplitDistance, TheTalksOnAGpuFartherOnACpuDeviceAndTheFlagWins) {
  CloudRenderOptions o;
  EXPECT_EQ(split_distance_for_device(o, false), 200.0f);  // talk: "< 200 Meters: 480px * 270px"
  EXPECT_EQ(split_distance_for_device(o, true), kCpuSplitDistanceM);
  EXPECT_GT(kCpuSplitDistanceM, 200.0f);
  o.split_distance_m = 150.0f;  // --cloud-split-distance 150
  EXPECT_EQ(split_distance_for_device(o, true), 150.0f);
  EXPECT_EQ(split_distance_for_device(o, false), 150.0f);
}

TEST_F(CloudAssets, CacheKeepsOneCopyPerCanonicalPath) {
  CloudAssetCache cache(ctx());
  const auto& data = test_data();
  auto a = cache.cloudscape(data.cloudscape, {});
  auto b = cache.cloudscape(data.cloudscape / "." / ".." / "cloudscape", {});
  EXPECT_EQ(a.get(), b.get());
  auto n1 = cache.noise(data.noise);
  auto n2 = cache.noise(data.root / "." / "voxel_noise.nvdf");
  EXPECT_EQ(n1.get(), n2.get());
  EXPECT_EQ(n1->size, 32u);
  EXPECT_EQ(n1->mips, 6u);
  EXPECT_EQ(cache.size(), 2u);
  auto field16 = cache.cloudscape(data.cloudscape, CloudFormats{false, false});
  EXPECT_EQ(field16.get(), a.get());
  if (ctx().info().texture_compression_bc) {
    auto bc1 = cache.cloudscape(data.cloudscape, CloudFormats{false, true});  // another format: another copy
    EXPECT_NE(bc1.get(), a.get());
    EXPECT_EQ(cache.size(), 3u);
  }
}

TEST_F(CloudAssets, MissingAndBadFilesNameTheFile) {
  const auto& data = test_data();
  std::string e = error_of([&] { load_cloud_asset(ctx(), data.root / "nowhere", {}); });
  EXPECT_NE(e.find("nowhere"), std::string::npos) << e;

  const fs::path missing = copy_folder(data.cloudscape, "missing_field");
  fs::remove(missing / kFieldFileName);
  e = error_of([&] { load_cloud_asset(ctx(), missing, {}); });
  EXPECT_NE(e.find("missing_field/field.nvdf"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;

  const fs::path truncated = copy_folder(data.cloudscape, "truncated");
  fs::resize_file(truncated / kModelingFileName, 100);
  e = error_of([&] { load_cloud_asset(ctx(), truncated, {}); });
  EXPECT_NE(e.find("truncated/modeling.nvdf"), std::string::npos) << e;

  const fs::path swapped = copy_folder(data.cloudscape, "swapped");  // a field where the modeling data belongs
  fs::copy_file(swapped / kFieldFileName, swapped / kModelingFileName, fs::copy_options::overwrite_existing);
  e = error_of([&] { load_cloud_asset(ctx(), swapped, {}); });
  EXPECT_NE(e.find("swapped/modeling.nvdf"), std::string::npos) << e;
  EXPECT_NE(e.find("encoding"), std::string::npos) << e;

  const fs::path wrong_noise = data.root / "not_noise.nvdf";
  fs::copy_file(data.cloudscape / kFieldFileName, wrong_noise, fs::copy_options::overwrite_existing);
  e = error_of([&] { load_cloud_noise(ctx(), wrong_noise); });
  EXPECT_NE(e.find("not_noise.nvdf"), std::string::npos) << e;

  e = error_of([&] { load_cloud_asset(ctx(), data.noise, {}); });  // a file, not a folder
  EXPECT_NE(e.find("voxel_noise.nvdf"), std::string::npos) << e;
}

// Coverage thresholds (nvdf.h): a folder from before them (no coverage.nvdf, a modeling.nvdf whose alpha is not
// declared) loads with threshold 0 everywhere, whatever its alpha bytes hold; a bad coverage.nvdf names itself.
TEST_F(CloudAssets, FoldersWithoutCoverageThresholdsLoadWithThresholdZero) {
  const auto& data = test_data();
  const fs::path old = copy_folder(data.cloudscape, "before_coverage");
  fs::remove(old / kCoverageFileName);
  Volume m = load_volume(old / kModelingFileName);
  ASSERT_EQ(m.channels.size(), 4u);
  m.channels.pop_back();  // as bakes before issue 20 wrote it: three channels, alpha unused
  for (size_t i = 3; i < m.levels[0].size(); i += 4) m.levels[0][i] = 200;
  save_volume(old / kModelingFileName, m);
  std::shared_ptr<CloudAsset> u = load_cloud_asset(ctx(), old, CloudFormats::from_set(CloudFormatSet::Uncompressed));
  const std::vector<uint8_t> texels = gpu::read_image_bytes(ctx(), u->modeling);
  ASSERT_EQ(texels.size(), m.levels[0].size());
  size_t nonzero_alpha = 0, same_rgb = 0;
  for (size_t i = 0; i < texels.size(); i += 4) {
    nonzero_alpha += texels[i + 3] != 0;
    same_rgb += texels[i] == m.levels[0][i] && texels[i + 1] == m.levels[0][i + 1] && texels[i + 2] == m.levels[0][i + 2];
  }
  EXPECT_EQ(nonzero_alpha, 0u);
  EXPECT_EQ(same_rgb, texels.size() / 4);
  if (!ctx().info().texture_compression_bc) GTEST_SKIP() << "no BC texture support";
  std::shared_ptr<CloudAsset> c = load_cloud_asset(ctx(), old, CloudFormats::from_set(CloudFormatSet::Compressed));
  EXPECT_EQ(c->coverage.extent().width, 1u);  // one texel of threshold 0
  EXPECT_EQ(gpu::read_image_bytes(ctx(), c->coverage), std::vector<uint8_t>{0});

  const fs::path bad = copy_folder(data.cloudscape, "bad_coverage");
  fs::copy_file(bad / kFieldFileName, bad / kCoverageFileName, fs::copy_options::overwrite_existing);
  const std::string e = error_of([&] { load_cloud_asset(ctx(), bad, CloudFormats::from_set(CloudFormatSet::Compressed)); });
  EXPECT_NE(e.find("bad_coverage/coverage.nvdf: encoding r16"), std::string::npos) << e;
}
