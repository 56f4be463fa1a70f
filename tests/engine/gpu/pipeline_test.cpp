#include "engine/gpu/pipeline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline_cache.h"
#include "engine/gpu/readback.h"
#include "engine/gpu/sampler.h"
#include "engine/gpu/timestamps.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;
using cumulo::gpu::test::GpuTest;
namespace fs = std::filesystem;

// Compiled at run time with an #include and a define; the written image is read back and checked
// texel by texel against the formula in shaders/test/test_common.glsl.
TEST_F(GpuTest, ComputeShaderWithIncludeAndDefineWritesImage) {
  ShaderCompiler compiler({}, cache_ / "shaders");
  Pipeline p = Pipeline::compute(ctx(), compiler,
                                 {.shader = "test/fill_pattern.comp", .defines = {{"SCALE", "3.0"}}, .name = "fill"});
  EXPECT_TRUE(p.set0_is_push());
  const uint32_t W = 64, H = 48;
  Image img(ctx(), ImageDesc::tex2d(W, H, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, 1, "pattern"));
  GpuTimer timer(ctx(), 1);
  timer.begin_frame(0);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    ctx().cmd_begin_label(cmd, "fill pattern");
    uint32_t t = timer.begin(cmd, "fill");
    cmd_image_barrier(cmd, img.handle(), img.full_range(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    p.bind(cmd);
    DescriptorWriter().storage_image(0, img.view()).push(ctx(), cmd, p);
    uint32_t size[2] = {W, H};
    p.push_constants(cmd, size, sizeof size);
    p.dispatch_threads(cmd, W, H);
    timer.end(cmd, t);
    ctx().cmd_end_label(cmd);
  });
  img.set_layout(VK_IMAGE_LAYOUT_GENERAL);
  std::vector<uint8_t> raw = read_image_bytes(ctx(), img);
  ASSERT_EQ(raw.size(), W * H * 16);
  const float* f = reinterpret_cast<const float*>(raw.data());
  int bad = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      const float* t = f + (y * W + x) * 4;
      if (t[0] != x / 64.0f || t[1] != y / 64.0f || t[2] != 3.0f || t[3] != float(x + y)) ++bad;
    }
  EXPECT_EQ(bad, 0);
  auto ranges = timer.collect(0);
  ASSERT_EQ(ranges.size(), 1u);
  EXPECT_EQ(ranges[0].name, "fill");
  EXPECT_GT(ranges[0].ms, 0.0);
  EXPECT_LT(ranges[0].ms, 10000.0);
}

// A 3D texture with a full mip chain uploaded from CPU data, sampled with textureLod in a compute shader.
TEST_F(GpuTest, Texture3DWithMipsUploadAndSample) {
  const uint32_t N = 8;
  Image vol(ctx(), ImageDesc::tex3d(N, N, N, VK_FORMAT_R8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT, kAllMips, "volume"));
  ASSERT_EQ(vol.mips(), 4u);
  // Mip 0: value = x / 7 (a ramp along x); mip m > 0: constant 40 * m / 255.
  std::vector<std::vector<uint8_t>> mips;
  for (uint32_t m = 0; m < vol.mips(); ++m) {
    VkExtent3D e = vol.extent(m);
    std::vector<uint8_t> d(size_t(e.width) * e.height * e.depth);
    for (size_t i = 0; i < d.size(); ++i) d[i] = m == 0 ? uint8_t(std::lround((i % N) * 255.0 / 7.0)) : uint8_t(40 * m);
    mips.push_back(std::move(d));
  }
  std::vector<MipData> md;
  for (auto& d : mips) md.push_back({d.data(), d.size()});
  vol.upload(md);
  EXPECT_EQ(vol.layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

  struct Q {
    float u, v, w, lod;
  };
  std::vector<Q> queries = {
      {0.5f / N, 0.5f, 0.5f, 0.0f},  // texel 0 centre -> 0
      {7.5f / N, 0.5f, 0.5f, 0.0f},  // texel 7 centre -> 1
      {4.0f / N, 0.3f, 0.7f, 0.0f},  // between texels 3 and 4 -> (3/7 + 4/7) / 2 = 0.5 (trilinear along x)
      {0.5f, 0.5f, 0.5f, 1.0f},     {0.5f, 0.5f, 0.5f, 2.0f},
      {0.5f, 0.5f, 0.5f, 3.0f},     {0.5f, 0.5f, 0.5f, 1.5f},  // between mips 1 and 2 -> (40 + 80) / 2 / 255
  };
  std::vector<float> expected = {0.0f, 1.0f, 0.5f, 40 / 255.0f, 80 / 255.0f, 120 / 255.0f, 60 / 255.0f};
  Buffer qbuf(ctx(),
              {.size = queries.size() * sizeof(Q), .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "queries"});
  qbuf.upload(queries.data(), queries.size() * sizeof(Q));
  Buffer rbuf(ctx(), {.size = queries.size() * 16, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "results"});

  ShaderCompiler compiler({}, cache_ / "shaders");
  Pipeline p = Pipeline::compute(ctx(), compiler, {.shader = "test/sample_volume.comp", .name = "sample volume"});
  VkSampler sampler = ctx().samplers().get(SamplerDesc::linear_clamp());
  EXPECT_EQ(ctx().samplers().get(SamplerDesc::linear_clamp()), sampler);  // cached
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    p.bind(cmd);
    DescriptorWriter()
        .sampled_image(0, vol.view(), sampler)
        .storage_buffer(1, rbuf.handle())
        .storage_buffer(2, qbuf.handle())
        .push(ctx(), cmd, p);
    p.dispatch_threads(cmd, uint32_t(queries.size()));
  });
  std::vector<float> res(queries.size() * 4);
  rbuf.download(res.data(), res.size() * 4);
  // R8 quantization (1/255) plus filtering precision on lavapipe (8-bit filter weights).
  for (size_t i = 0; i < queries.size(); ++i) EXPECT_NEAR(res[i * 4], expected[i], 2.5 / 255.0) << "query " << i;
}

TEST_F(GpuTest, GraphicsPipelineRendersAndWritesPng) {
  ShaderCompiler compiler({}, cache_ / "shaders");
  const VkFormat fmt = VK_FORMAT_R8G8B8A8_UNORM;
  Pipeline p = Pipeline::graphics(ctx(), compiler,
                                  {.vertex = "test/solid_color.vert",
                                   .fragment = "test/solid_color.frag",
                                   .color_formats = {fmt},
                                   .name = "solid"});
  EXPECT_EQ(p.push_constant_size(), 20u);
  const uint32_t W = 64, H = 64;
  Image target(ctx(), ImageDesc::tex2d(W, H, fmt, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, 1, "target"));
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    cmd_image_barrier(cmd, target.handle(), target.full_range(), VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, 0,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = target.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {W, H}};
    ri.layerCount = 1;
    ri.colorAttachmentCount = 1;
    ri.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &ri);
    p.bind(cmd);
    VkViewport vp{0, 0, float(W), float(H), 0, 1};
    VkRect2D sc{{0, 0}, {W, H}};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &sc);
    struct {
      float color[4];
      float split;
    } push = {{1.0f, 0.25f, 0.0f, 1.0f}, 32.0f};
    p.push_constants(cmd, &push, sizeof push);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  });
  target.set_layout(VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
  Rgba8Image shot = read_image_rgba8(ctx(), target);
  ASSERT_EQ(shot.width, W);
  EXPECT_EQ(shot.at(5, 5)[0], 255);
  EXPECT_EQ(shot.at(5, 5)[1], 64);
  EXPECT_EQ(shot.at(60, 40)[0], 0);
  EXPECT_EQ(shot.at(60, 40)[1], 191);
  EXPECT_EQ(shot.at(60, 40)[2], 255);
  fs::path png = cache_ / "out" / "solid.png";
  write_png(png, shot);
  EXPECT_GT(fs::file_size(png), 50u);
}

TEST_F(GpuTest, PipelineCacheFileWrittenAndReloaded) {
  fs::path file = ctx().pipeline_cache().file();
  EXPECT_EQ(file, cache_ / "pipelines.bin");
  EXPECT_FALSE(ctx().pipeline_cache().loaded_from_disk());
  ShaderCompiler compiler({}, cache_ / "shaders");
  { Pipeline p = Pipeline::compute(ctx(), compiler, {.shader = "test/fill_pattern.comp"}); }
  ctx().pipeline_cache().save();
  ASSERT_TRUE(fs::exists(file));
  EXPECT_GE(fs::file_size(file), sizeof(VkPipelineCacheHeaderVersionOne));  // lavapipe stores just the header
  // A second context on the same folder starts from the file.
  ctx_.reset();
  ContextDesc desc;
  desc.validation = true;
  desc.cache_dir = cache_;
  ctx_ = std::make_unique<Context>(desc);
  EXPECT_TRUE(ctx().pipeline_cache().loaded_from_disk());
  // A garbled file is ignored, not fatal.
  ctx_.reset();
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      << "not a pipeline cache, just some bytes that are long enough";
  ctx_ = std::make_unique<Context>(desc);
  EXPECT_FALSE(ctx().pipeline_cache().loaded_from_disk());
}

TEST_F(GpuTest, PushToWrongBindingIsAnError) {
  ShaderCompiler compiler({}, cache_ / "shaders");
  Pipeline p = Pipeline::compute(ctx(), compiler, {.shader = "test/fill_pattern.comp", .name = "fill"});
  Buffer b(ctx(), {.size = 64, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
  EXPECT_THROW(ctx().submit_and_wait(
                   [&](VkCommandBuffer cmd) { DescriptorWriter().storage_buffer(0, b.handle()).push(ctx(), cmd, p); }),
               cumulo::Error);
  EXPECT_THROW(ctx().submit_and_wait(
                   [&](VkCommandBuffer cmd) { DescriptorWriter().storage_buffer(5, b.handle()).push(ctx(), cmd, p); }),
               cumulo::Error);
}

// BC1 (the format of the talk's conservative SDF option): two 4x4 blocks decoded by the device.
TEST_F(GpuTest, Bc1TextureDecodesWhenSampled) {
  ASSERT_TRUE(ctx().info().texture_compression_bc);
  Image tex(ctx(), ImageDesc::tex2d(8, 4, VK_FORMAT_BC1_RGB_UNORM_BLOCK, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "bc1"));
  // Block layout: color0 (RGB565), color1, then 2-bit indices. color0 > color1 selects 4-colour mode.
  // Block 0: all texels index 0 (red); block 1: all texels index 1 (blue).
  const uint8_t blocks[16] = {0x00, 0xF8, 0x1F, 0x00, 0x00, 0x00, 0x00, 0x00,
                              0x00, 0xF8, 0x1F, 0x00, 0x55, 0x55, 0x55, 0x55};
  tex.upload({{blocks, sizeof blocks}});
  struct Q {
    float u, v, pad, lod;
  };
  std::vector<Q> q = {{1.5f / 8, 0.5f, 0, 0}, {6.5f / 8, 0.5f, 0, 0}};
  Buffer qbuf(ctx(), {.size = sizeof(Q) * q.size(), .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
  qbuf.upload(q.data(), sizeof(Q) * q.size());
  Buffer rbuf(ctx(), {.size = 16 * q.size(), .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
  ShaderCompiler compiler({}, cache_ / "shaders");
  Pipeline p = Pipeline::compute(ctx(), compiler, {.shader = "test/sample_texture2d.comp"});
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    p.bind(cmd);
    DescriptorWriter()
        .sampled_image(0, tex.view(), ctx().samplers().get(SamplerDesc::nearest_clamp()))
        .storage_buffer(1, rbuf.handle())
        .storage_buffer(2, qbuf.handle())
        .push(ctx(), cmd, p);
    p.dispatch_threads(cmd, uint32_t(q.size()));
  });
  float r[8];
  rbuf.download(r, sizeof r);
  EXPECT_NEAR(r[0], 1.0f, 0.01f);
  EXPECT_NEAR(r[2], 0.0f, 0.01f);
  EXPECT_NEAR(r[4], 0.0f, 0.01f);
  EXPECT_NEAR(r[6], 1.0f, 0.01f);
}
