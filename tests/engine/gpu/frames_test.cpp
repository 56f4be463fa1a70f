#include "engine/gpu/frames.h"

#include <gtest/gtest.h>

#include "engine/gpu/barrier.h"
#include "engine/gpu/image.h"
#include "engine/gpu/readback.h"
#include "engine/gpu/timestamps.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;
using cumulo::gpu::test::GpuTest;

// Headless frame loop: 2 slots round-robin, per-slot timestamps read back once the slot comes around.
TEST_F(GpuTest, FrameRingCyclesSlotsWithTimestamps) {
  FrameRing frames(ctx());
  GpuTimer timer(ctx(), frames.size());
  Image target(ctx(),
               ImageDesc::tex2d(32, 32, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_TRANSFER_DST_BIT, 1, "frame target"));
  std::vector<uint32_t> slots;
  size_t ranges_seen = 0;
  for (int i = 0; i < 5; ++i) {
    Frame& f = frames.begin();
    slots.push_back(f.slot);
    const auto& prev = timer.begin_frame(f.slot);
    if (i >= 2) {
      ASSERT_EQ(prev.size(), 1u);
      EXPECT_EQ(prev[0].name, "clear");
      EXPECT_GT(prev[0].ms, 0.0);
      ranges_seen++;
    }
    uint32_t t = timer.begin(f.cmd, "clear");
    // Each frame overwrites the whole image: wait for the previous frame's clear (WAW) before clearing.
    cmd_image_barrier(f.cmd, target.handle(), target.full_range(), VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkClearColorValue c{{float(i) / 4.0f, 0.0f, 1.0f, 1.0f}};
    VkImageSubresourceRange range = target.full_range();
    vkCmdClearColorImage(f.cmd, target.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &c, 1, &range);
    timer.end(f.cmd, t);
    frames.submit(f);
  }
  frames.wait_all();
  EXPECT_EQ(slots, (std::vector<uint32_t>{0, 1, 0, 1, 0}));
  EXPECT_EQ(ranges_seen, 3u);
  target.set_layout(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  Rgba8Image shot = read_image_rgba8(ctx(), target);
  EXPECT_EQ(shot.at(3, 3)[0], 255);  // the last frame (i = 4) cleared to 1.0
}
