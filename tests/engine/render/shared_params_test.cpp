// The shared CPU/GPU parameter blocks must have the std140/std430 layout the shaders expect:
// sizes are static_assert'ed in the header; offsets are checked here against the GLSL rules.
#include <cstddef>

#include <gtest/gtest.h>

#include "shaders/shared/frame_params.h"

using namespace cumulo::shared;

TEST(SharedParams, FrameParamsOffsetsFollowStd140) {
  EXPECT_EQ(offsetof(FrameParams, view_proj), 0u);
  EXPECT_EQ(offsetof(FrameParams, inv_view_proj), 64u);
  EXPECT_EQ(offsetof(FrameParams, camera_pos), 128u);
  EXPECT_EQ(offsetof(FrameParams, sun_dir), 144u);
  EXPECT_EQ(offsetof(FrameParams, viewport), 224u);
  EXPECT_EQ(sizeof(FrameParams) % 16, 0u);
}

TEST(SharedParams, PushConstantBlocksFitTheGuaranteedLimit) {
  // Vulkan guarantees 128 bytes of push constants on every device.
  EXPECT_LE(sizeof(DrawParams), 128u);
  EXPECT_EQ(offsetof(DrawParams, material), 80u);
  EXPECT_LE(sizeof(TonemapParams), 128u);
  EXPECT_EQ(offsetof(DrawParams, base_color_factor), 64u);
}
