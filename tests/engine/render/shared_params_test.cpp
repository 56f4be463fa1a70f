// The shared CPU/GPU parameter blocks must have the std140/std430 layout the shaders expect:
// sizes are static_assert'ed in the header; offsets are checked here against the GLSL rules.
#include <cstddef>

#include <gtest/gtest.h>

#include "shaders/shared/frame_params.h"

using namespace cumulo::shared;

TEST(SharedParams, FrameParamsOffsetsFollowStd140) {
  EXPECT_EQ(offsetof(FrameParams, view_proj), 0u);
  EXPECT_EQ(offsetof(FrameParams, inv_view_proj), 64u);
  // std140: a vec3 starts on 16 bytes and the float after it fills its fourth component.
  EXPECT_EQ(offsetof(FrameParams, camera_position), 128u);
  EXPECT_EQ(offsetof(FrameParams, time_s), 140u);
  EXPECT_EQ(offsetof(FrameParams, sun_direction), 144u);
  EXPECT_EQ(offsetof(FrameParams, ambient), 156u);
  EXPECT_EQ(offsetof(FrameParams, sky_zenith), 176u);
  EXPECT_EQ(offsetof(FrameParams, ground_color), 208u);
  EXPECT_EQ(offsetof(FrameParams, viewport_size), 224u);
  EXPECT_EQ(offsetof(FrameParams, inv_viewport_size), 232u);
  EXPECT_EQ(sizeof(FrameParams) % 16, 0u);
}

TEST(SharedParams, PushConstantBlocksFitTheGuaranteedLimit) {
  // Vulkan guarantees 128 bytes of push constants on every device.
  EXPECT_LE(sizeof(DrawParams), 128u);
  EXPECT_EQ(offsetof(DrawParams, roughness), 80u);
  EXPECT_EQ(offsetof(DrawParams, double_sided), 88u);
  EXPECT_LE(sizeof(TonemapParams), 128u);
  EXPECT_EQ(offsetof(DrawParams, base_color_factor), 64u);
}
