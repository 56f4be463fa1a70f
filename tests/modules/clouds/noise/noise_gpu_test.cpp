// The voxel noise on the GPU (lavapipe in CI, validation on): both storage formats are supported for
// sampled, filtered 3D textures, and the GPU reads back exactly the channel values the CPU stored,
// at every mip level (this pins our R4G4B4A4 bit order to Vulkan's packed 4-bit formats).
#include <gtest/gtest.h>

#include "engine/core/file_io.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/sampler.h"
#include "modules/clouds/noise/noise_encode.h"
#include "tests/engine/gpu/gpu_test_util.h"
#include "tests/modules/clouds/noise/noise_gpu_util.h"

namespace cumulo::clouds {
namespace {

using gpu::test::GpuTest;

TEST_F(GpuTest, NoiseFormatsAreSampleable) {
  EXPECT_TRUE(test::noise_format_supported(ctx(), VK_FORMAT_R8G8B8A8_UNORM));
  // B4G4R4A4 has mandatory sampled + linear support; R4G4B4A4 is optional (lavapipe: no).
  EXPECT_TRUE(test::noise_format_supported(ctx(), VK_FORMAT_B4G4R4A4_UNORM_PACK16));
  test::NoiseGpuFormat f = test::noise_gpu_format(ctx(), VolumeEncoding::R4G4B4A4);
  EXPECT_TRUE(test::noise_format_supported(ctx(), f.format));
  RecordProperty("r4g4b4a4_unorm_pack16", test::noise_format_supported(ctx(), VK_FORMAT_R4G4B4A4_UNORM_PACK16) ? "yes" : "no");
}

TEST_F(GpuTest, NoiseTexelsReadBackOnTheGpu) {
  VoxelNoiseParams p;
  p.size = 16;
  p.seed = 9;
  NoiseTexture tex = generate_voxel_noise(p);
  const std::vector<NoiseChannelInfo> ch = {{"r"}, {"g"}, {"b"}, {"a"}};

  // Texel centres of levels 0..2 (linear filtering at a centre returns the texel itself).
  struct Q {
    float u, v, w, lod;
  };
  struct Expect {
    uint32_t x, y, z, level;
  };
  std::vector<Q> queries;
  std::vector<Expect> where;
  for (uint32_t level = 0; level < 3; ++level) {
    uint32_t n = 16u >> level;
    for (uint32_t i = 0; i < 24; ++i) {
      uint32_t x = (i * 5) % n, y = (i * 3 + 1) % n, z = (i * 7 + 2) % n;
      queries.push_back({(x + 0.5f) / n, (y + 0.5f) / n, (z + 0.5f) / n, static_cast<float>(level)});
      where.push_back({x, y, z, level});
    }
  }
  gpu::ShaderCompiler compiler({}, cache_ / "shaders");
  gpu::Pipeline pipeline = gpu::Pipeline::compute(
      ctx(), compiler, {.shader = repo_root() / "tests/modules/clouds/noise/noise_sample.comp", .name = "noise sample"});
  gpu::Buffer qbuf(ctx(), {.size = queries.size() * sizeof(Q), .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "queries"});
  qbuf.upload(queries.data(), queries.size() * sizeof(Q));
  gpu::Buffer rbuf(ctx(), {.size = queries.size() * 16, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "results"});
  VkSampler sampler = ctx().samplers().get(gpu::SamplerDesc::linear_repeat());

  for (VolumeEncoding e : {VolumeEncoding::R4G4B4A4, VolumeEncoding::RGBA8}) {
    Volume vol = noise_to_volume(tex, e, ch);
    test::NoiseImage image(ctx(), vol, "voxel noise");
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
      pipeline.bind(cmd);
      gpu::DescriptorWriter()
          .sampled_image(0, image.view(), sampler)
          .storage_buffer(1, rbuf.handle())
          .storage_buffer(2, qbuf.handle())
          .push(ctx(), cmd, pipeline);
      uint32_t count = static_cast<uint32_t>(queries.size());
      pipeline.push_constants(cmd, count);
      pipeline.dispatch_threads(cmd, count);
    });
    std::vector<float> res(queries.size() * 4);
    rbuf.download(res.data(), res.size() * sizeof(float));
    for (size_t i = 0; i < where.size(); ++i)
      for (uint32_t c = 0; c < 4; ++c)
        ASSERT_NEAR(res[i * 4 + c], vol.texel(where[i].x, where[i].y, where[i].z, c, where[i].level), 1.0f / 512.0f)
            << encoding_name(e) << " level " << where[i].level << " texel " << where[i].x << "," << where[i].y << ","
            << where[i].z << " channel " << c;
  }
}

}  // namespace
}  // namespace cumulo::clouds
