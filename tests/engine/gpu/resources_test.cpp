#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>

#include "engine/core/error.h"
#include "engine/gpu/allocator.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/format.h"
#include "engine/gpu/image.h"
#include "engine/gpu/readback.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;
using cumulo::gpu::test::GpuTest;

TEST_F(GpuTest, BufferUploadDownloadRoundtripDeviceLocal) {
  std::vector<uint32_t> data(10000);
  std::iota(data.begin(), data.end(), 7u);
  Buffer buf(ctx(), {.size = data.size() * 4, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "roundtrip"});
  buf.upload(data.data(), data.size() * 4);
  std::vector<uint32_t> back(data.size());
  buf.download(back.data(), back.size() * 4);
  EXPECT_EQ(back, data);
  // Partial update at an offset through the same path.
  uint32_t patch[3] = {1, 2, 3};
  buf.upload(patch, sizeof patch, 400);
  buf.download(back.data(), back.size() * 4);
  EXPECT_EQ(back[100], 1u);
  EXPECT_EQ(back[102], 3u);
  EXPECT_EQ(back[103], data[103]);
}

TEST_F(GpuTest, BufferHostVisibleIsMappedAndOverflowIsAnError) {
  Buffer ubo(ctx(), {.size = 256, .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, .memory = MemoryUsage::Dynamic});
  ASSERT_NE(ubo.mapped(), nullptr);
  float v[4] = {1, 2, 3, 4};
  ubo.upload(v, sizeof v);
  EXPECT_EQ(ubo.mapped_as<float>()[2], 3.0f);
  EXPECT_THROW(ubo.upload(v, sizeof v, 250), cumulo::Error);
}

TEST_F(GpuTest, AllocatorSuballocatesAndTracksPeak) {
  MemoryStats before = ctx().allocator().stats();
  std::vector<Buffer> bufs;
  for (int i = 0; i < 32; ++i)
    bufs.emplace_back(ctx(), BufferDesc{.size = 4096 + uint64_t(i) * 100, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
  MemoryStats mid = ctx().allocator().stats();
  EXPECT_EQ(mid.allocation_count, before.allocation_count + 32);
  EXPECT_LE(mid.block_count, before.block_count + 1) << "32 small buffers must share one block";
  // Distinct buffers in the same block never overlap.
  for (size_t i = 0; i < bufs.size(); ++i)
    for (size_t j = i + 1; j < bufs.size(); ++j) {
      const Allocation &a = bufs[i].allocation(), &b = bufs[j].allocation();
      if (a.memory != b.memory) continue;
      EXPECT_TRUE(a.offset + a.size <= b.offset || b.offset + b.size <= a.offset);
    }
  uint64_t peak = mid.allocated_bytes;
  bufs.clear();
  MemoryStats after = ctx().allocator().stats();
  EXPECT_EQ(after.allocated_bytes, before.allocated_bytes);
  EXPECT_GE(after.peak_allocated_bytes, peak);
  // A request over half a block gets a dedicated block that is released on free.
  {
    Buffer big(ctx(), {.size = 40ull << 20, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "big"});
    EXPECT_EQ(ctx().allocator().stats().block_count, after.block_count + 1);
  }
  EXPECT_EQ(ctx().allocator().stats().block_count, after.block_count);
}

// Two images bound to one allocation (render-graph aliasing) are each usable in turn.
TEST_F(GpuTest, ImagesAliasOneAllocation) {
  auto da = ImageDesc::tex2d(32, 32, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_STORAGE_BIT, 1, "alias a");
  auto db = ImageDesc::tex2d(16, 16, VK_FORMAT_R32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, 1, "alias b");
  Image a = Image::create_unbound(ctx(), da), b = Image::create_unbound(ctx(), db);
  VkMemoryRequirements ra = a.memory_requirements(), rb = b.memory_requirements();
  VkMemoryRequirements combined{std::max(ra.size, rb.size), std::max(ra.alignment, rb.alignment),
                                ra.memoryTypeBits & rb.memoryTypeBits};
  Allocation mem = ctx().allocator().allocate(combined, MemoryUsage::GpuOnly, "alias slot");
  a.bind_memory(mem);
  b.bind_memory(mem);
  std::vector<uint8_t> pa(32 * 32 * 4, 200);
  a.upload({{pa.data(), pa.size()}}, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(read_image_bytes(ctx(), a)[5], 200);
  // b now takes over the memory (contents undefined -> upload defines them).
  std::vector<float> pb(16 * 16, 0.5f);
  b.upload({{pb.data(), pb.size() * 4}}, VK_IMAGE_LAYOUT_GENERAL);
  std::vector<uint8_t> rbk = read_image_bytes(ctx(), b);
  EXPECT_EQ(reinterpret_cast<float*>(rbk.data())[17], 0.5f);
  a.reset();
  b.reset();
  ctx().allocator().free(mem);
}

TEST_F(GpuTest, ImageUploadRejectsWrongSizeNamingTheMip) {
  Image img(ctx(), ImageDesc::tex2d(8, 8, VK_FORMAT_BC1_RGBA_UNORM_BLOCK, VK_IMAGE_USAGE_SAMPLED_BIT, kAllMips, "bc1"));
  EXPECT_EQ(img.mips(), 4u);
  EXPECT_EQ(mip_size_bytes(VK_FORMAT_BC1_RGBA_UNORM_BLOCK, {8, 8, 1}, 0), 32u);  // 2x2 blocks x 8 bytes
  EXPECT_EQ(mip_size_bytes(VK_FORMAT_BC1_RGBA_UNORM_BLOCK, {8, 8, 1}, 3), 8u);   // 1x1 texel still one block
  std::vector<uint8_t> blocks(32 + 8 + 8 + 8, 0);
  img.upload({{blocks.data(), 32}, {blocks.data(), 8}, {blocks.data(), 8}, {blocks.data(), 8}});
  try {
    img.upload({{blocks.data(), 31}});
    FAIL();
  } catch (const cumulo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("mip 0"), std::string::npos) << e.what();
  }
}

TEST(Readback, ConvertsFormatsToRgba8) {
  uint16_t half[4] = {0x3c00, 0x3800, 0x0000, 0x3c00};  // 1.0, 0.5, 0, 1
  auto out = convert_to_rgba8(VK_FORMAT_R16G16B16A16_SFLOAT, half, 1);
  EXPECT_EQ(out[0], 255);
  EXPECT_EQ(out[1], 128);
  EXPECT_EQ(out[2], 0);
  uint8_t bgra[4] = {10, 20, 30, 40};
  out = convert_to_rgba8(VK_FORMAT_B8G8R8A8_UNORM, bgra, 1);
  EXPECT_EQ(out[0], 30);
  EXPECT_EQ(out[2], 10);
  float f = 0.5f;
  out = convert_to_rgba8(VK_FORMAT_R32_SFLOAT, &f, 1, /*srgb_encode=*/true);
  EXPECT_EQ(out[0], 188);  // sRGB(0.5) = 0.7354
  EXPECT_FLOAT_EQ(half_to_float(0x0001), std::ldexp(1.0f, -24));
  EXPECT_THROW(convert_to_rgba8(VK_FORMAT_BC1_RGBA_UNORM_BLOCK, bgra, 1), cumulo::Error);
}

TEST(Readback, WritePngToBadPathNamesIt) {
  Rgba8Image img{2, 2, std::vector<uint8_t>(16, 255)};
  try {
    write_png("/proc/cumulo_no_such_dir/x.png", img);
    FAIL();
  } catch (const cumulo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/cumulo_no_such_dir/x.png"), std::string::npos);
  }
}

// Mips generated on the GPU by blits: a 3D volume and a 2D image with a checkerboard average.
TEST_F(GpuTest, GenerateMipsByBlit) {
  Image vol(ctx(), ImageDesc::tex3d(8, 8, 8, VK_FORMAT_R8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT, kAllMips, "mip volume"));
  std::vector<uint8_t> v(8 * 8 * 8, 100);
  vol.upload({{v.data(), v.size()}}, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { vol.cmd_generate_mips(cmd); });
  EXPECT_EQ(vol.layout(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  for (uint32_t m = 1; m < vol.mips(); ++m) {
    std::vector<uint8_t> got = read_image_bytes(ctx(), vol, m);
    ASSERT_EQ(got.size(), size_t(8 >> m) * (8 >> m) * (8 >> m));
    for (uint8_t x : got) EXPECT_NEAR(x, 100, 1) << "mip " << m;
  }
  Image img(ctx(),
            ImageDesc::tex2d(4, 4, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, kAllMips, "mip 2d"));
  std::vector<uint16_t> px(4 * 4 * 4);
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 4; ++c) px[i * 4 + c] = ((i % 4 + i / 4) % 2) ? 0x3c00 : 0x0000;  // checkerboard of 1.0 and 0.0
  img.upload({{px.data(), px.size() * 2}});
  ctx().submit_and_wait([&](VkCommandBuffer cmd) { img.cmd_generate_mips(cmd); });
  std::vector<uint8_t> top = read_image_bytes(ctx(), img, 2);
  ASSERT_EQ(top.size(), 8u);
  uint16_t h;
  std::memcpy(&h, top.data(), 2);
  EXPECT_NEAR(half_to_float(h), 0.5f, 0.01f);
}

TEST_F(GpuTest, DepthImageReadback) {
  Image depth(ctx(),
              ImageDesc::tex2d(16, 8, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 1, "depth"));
  ASSERT_NE(depth.view(), VK_NULL_HANDLE);
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    depth.cmd_transition(cmd, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkClearDepthStencilValue v{0.25f, 0};
    VkImageSubresourceRange range = depth.full_range();
    vkCmdClearDepthStencilImage(cmd, depth.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &v, 1, &range);
  });
  std::vector<uint8_t> raw = read_image_bytes(ctx(), depth);
  ASSERT_EQ(raw.size(), 16u * 8u * 4u);
  float f;
  std::memcpy(&f, raw.data() + 4 * 37, 4);
  EXPECT_EQ(f, 0.25f);
  Rgba8Image shot = read_image_rgba8(ctx(), depth);
  EXPECT_EQ(shot.at(3, 3)[0], 64);
}
