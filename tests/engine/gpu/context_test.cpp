#include "engine/gpu/context.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "engine/gpu/allocator.h"
#include "engine/gpu/pipeline_cache.h"
#include "gpu_test_util.h"

using namespace cumulo;
using namespace cumulo::gpu;
using cumulo::gpu::test::GpuTest;

TEST_F(GpuTest, ContextCreatesDeviceWithZeroValidationErrors) {
  const DeviceInfo& info = ctx().info();
  EXPECT_FALSE(info.name.empty());
  EXPECT_GE(info.api_version, VK_API_VERSION_1_3);
  EXPECT_NE(ctx().device(), VK_NULL_HANDLE);
  EXPECT_NE(ctx().queue(), VK_NULL_HANDLE);
  EXPECT_TRUE(info.timestamps);
  if (info.driver_name == "llvmpipe") {
    EXPECT_NE(info.driver_info.find("Mesa"), std::string::npos) << info.driver_info;
    EXPECT_TRUE(info.texture_compression_bc);
    EXPECT_TRUE(info.push_descriptors);
    EXPECT_TRUE(info.is_cpu());
  }
  EXPECT_TRUE(ctx().debug_utils());
  if (info.push_descriptors) EXPECT_GE(info.max_push_descriptors, 32u);
}

TEST_F(GpuTest, SubmitAndWaitRunsCommandsWithLabels) {
  bool recorded = false;
  ctx().submit_and_wait([&](VkCommandBuffer cmd) {
    ctx().cmd_begin_label(cmd, "test label");
    ctx().cmd_end_label(cmd);
    recorded = true;
  });
  EXPECT_TRUE(recorded);
  ctx().wait_idle();
}

// The counting must actually work, or every "zero errors" assertion is vacuous: provoke one error
// on purpose (a fence created with an invalid flag) and check it is counted, in a separate Context.
TEST(GpuValidation, MessagesAreCounted) {
  cumulo::test::TempDir tmp("cumulo_gpu_validation_counting");
  ContextDesc desc;
  desc.validation = true;
  desc.cache_dir = tmp.path;
  Context ctx(desc);
  ASSERT_TRUE(ctx.validation_enabled());
  uint32_t before = total_validation_errors();
  VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  info.flags = 0x80;  // not a valid VkFenceCreateFlagBits value: VUID-VkFenceCreateInfo-flags-parameter
  VkFence fence = VK_NULL_HANDLE;
  vkCreateFence(ctx.device(), &info, nullptr, &fence);
  if (fence) vkDestroyFence(ctx.device(), fence, nullptr);
  EXPECT_GE(ctx.validation_errors(), 1u);
  EXPECT_GE(total_validation_errors(), before + 1);
  EXPECT_NE(ctx.last_validation_message().find("flags"), std::string::npos) << ctx.last_validation_message();
}

TEST(GpuContext, UnknownDeviceOverrideIsAClearError) {
  cumulo::test::TempDir tmp("cumulo_gpu_bad_device");
  ContextDesc desc;
  desc.device = "no-such-gpu-xyz";
  desc.cache_dir = tmp.path;
  try {
    Context ctx(desc);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("no-such-gpu-xyz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("devices:"), std::string::npos) << msg;
  }
}

// Synchronization validation must be on: two transfer writes to one buffer with no barrier between
// them are a WRITE_AFTER_WRITE hazard.
TEST(GpuValidation, SynchronizationValidationCatchesMissingBarrier) {
  cumulo::test::TempDir tmp("cumulo_gpu_sync_validation");
  ContextDesc desc;
  desc.validation = true;
  desc.cache_dir = tmp.path;
  Context ctx(desc);
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = 256;
  bi.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  VkBuffer buf;
  ASSERT_EQ(vkCreateBuffer(ctx.device(), &bi, nullptr, &buf), VK_SUCCESS);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buf, &req);
  Allocation a = ctx.allocator().allocate(req, MemoryUsage::GpuOnly);
  vkBindBufferMemory(ctx.device(), buf, a.memory, a.offset);
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, buf, 0, 256, 1);
    vkCmdFillBuffer(cmd, buf, 0, 256, 2);  // hazard: no barrier
  });
  EXPECT_GE(ctx.validation_errors(), 1u);
  EXPECT_NE(ctx.last_validation_message().find("WRITE_AFTER_WRITE"), std::string::npos)
      << ctx.last_validation_message();
  vkDestroyBuffer(ctx.device(), buf, nullptr);
  ctx.allocator().free(a);
}

TEST_F(GpuTest, NestedSubmitAndWaitIsAClearError) {
  EXPECT_THROW(ctx().submit_and_wait([&](VkCommandBuffer) { ctx().submit_and_wait([](VkCommandBuffer) {}); }),
               cumulo::Error);
  ctx().submit_and_wait([](VkCommandBuffer) {});  // still usable afterwards
}
