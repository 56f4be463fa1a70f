#include "engine/app/fly_camera.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

using namespace cumulo::app;
using cumulo::platform::InputState;
using cumulo::platform::Key;
using cumulo::platform::MouseButton;

static void press(InputState& s, Key k) { s.down[static_cast<size_t>(k)] = true; }

TEST(FlyCamera, DefaultLooksDownNegativeZ) {
  FlyCamera c;
  glm::vec3 f = fly_forward(c);
  EXPECT_NEAR(f.z, -1.0f, 1e-6f);
  glm::vec4 p = fly_view_matrix(c) * glm::vec4(0, 0, -10, 1);
  EXPECT_NEAR(p.z, -10.0f, 1e-5f);  // in front of the camera in view space
}

TEST(FlyCamera, WMovesForwardShiftIsFasterQDescends) {
  FlyCamera c;
  c.speed = 10.0f;
  InputState in;
  press(in, Key::W);
  EXPECT_TRUE(update_fly_camera(c, in, 0.5f));
  EXPECT_NEAR(c.position.z, -5.0f, 1e-5f);
  press(in, Key::LeftShift);
  update_fly_camera(c, in, 0.5f);
  EXPECT_NEAR(c.position.z, -45.0f, 1e-4f);
  InputState down;
  press(down, Key::Q);
  update_fly_camera(c, down, 1.0f);
  EXPECT_NEAR(c.position.y, -10.0f, 1e-5f);
}

TEST(FlyCamera, MouseLooksOnlyWithRightButtonOrCapture) {
  FlyCamera c;
  InputState in;
  in.mouse_dx = 100;
  EXPECT_FALSE(update_fly_camera(c, in, 0.016f));
  EXPECT_EQ(c.yaw, 0.0f);
  in.mouse_down[static_cast<size_t>(MouseButton::Right)] = true;
  EXPECT_TRUE(update_fly_camera(c, in, 0.016f));
  EXPECT_LT(c.yaw, 0.0f);  // moving the mouse right turns right (toward +X)
  EXPECT_GT(fly_forward(c).x, 0.0f);
  in.mouse_dy = -1e6;  // pitch clamps short of straight up
  update_fly_camera(c, in, 0.016f);
  EXPECT_LT(c.pitch, glm::radians(89.5f));
}

TEST(FlyCamera, LookAlongRoundTrips) {
  FlyCamera c;
  glm::vec3 d = glm::normalize(glm::vec3(0.3f, 0.2f, 0.9f));
  fly_look_along(c, d);
  glm::vec3 f = fly_forward(c);
  EXPECT_NEAR(f.x, d.x, 1e-5f);
  EXPECT_NEAR(f.y, d.y, 1e-5f);
  EXPECT_NEAR(f.z, d.z, 1e-5f);
}
