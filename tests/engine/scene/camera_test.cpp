// Camera math: reversed-Z Vulkan projection, view matrices, look-at, Euler angles, frustum, named cameras.
#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "engine/scene/camera.h"
#include "scene_test_util.h"

using namespace cumulo;
using namespace cumulo::scene;
using scene::test::expect_error;

namespace {
bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-4f) { return glm::length(a - b) < eps; }
}  // namespace

TEST(Camera, ReversedZDepthIsOneAtNearAndZeroAtFar) {
  glm::mat4 p = perspective(glm::radians(60.0f), 16.0f / 9.0f, 0.1f, 50000.0f);
  auto depth = [&](float t) {
    glm::vec4 c = p * glm::vec4(0, 0, -t, 1);
    return c.z / c.w;
  };
  EXPECT_NEAR(depth(0.1f), 1.0f, 1e-6f);
  EXPECT_NEAR(depth(50000.0f), 0.0f, 1e-6f);
  EXPECT_GT(depth(1.0f), depth(2.0f));  // reversed: nearer is larger
  for (float t : {0.1f, 1.0f, 37.0f, 1000.0f, 20000.0f, 50000.0f})
    EXPECT_NEAR(linearize_depth(depth(t), 0.1f, 50000.0f), t, t * 1e-3f) << t;
}

TEST(Camera, ProjectionFlipsYForVulkanAndKeepsAspect) {
  glm::mat4 p = perspective(glm::radians(90.0f), 2.0f, 1.0f, 100.0f);
  // A point up and to the right of the view axis lands at +x and -y (Vulkan's y points down).
  glm::vec4 c = p * glm::vec4(1, 1, -1, 1);
  EXPECT_NEAR(c.x / c.w, 0.5f, 1e-6f);  // tan(45) = 1, divided by the aspect
  EXPECT_NEAR(c.y / c.w, -1.0f, 1e-6f);
}

TEST(Camera, LookAtFacesTheTargetWithYUp) {
  Transform t = Transform::look_at({1, 2, 3}, {11, 2, 3});
  EXPECT_TRUE(near(t.forward(), {1, 0, 0}));
  EXPECT_TRUE(near(t.up(), {0, 1, 0}));
  EXPECT_TRUE(near(t.right(), {0, 0, 1}));
  glm::mat4 v = view_matrix(t);
  EXPECT_TRUE(near(glm::vec3(v * glm::vec4(1, 2, 3, 1)), {0, 0, 0}));
  EXPECT_TRUE(near(glm::vec3(v * glm::vec4(11, 2, 3, 1)), {0, 0, -10}));
  // Straight up: still a valid orthonormal basis.
  Transform up = Transform::look_at({0, 0, 0}, {0, 100, 0});
  EXPECT_TRUE(near(up.forward(), {0, 1, 0}));
  EXPECT_NEAR(glm::dot(up.up(), up.forward()), 0.0f, 1e-5f);
}

TEST(Camera, EulerDegreesPitchUpYawLeftAndRoundTrip) {
  EXPECT_TRUE(near(euler_degrees_to_quat({30, 0, 0}) * glm::vec3(0, 0, -1), {0, 0.5f, -0.8660254f}));
  EXPECT_TRUE(near(euler_degrees_to_quat({0, 90, 0}) * glm::vec3(0, 0, -1), {-1, 0, 0}));
  for (glm::vec3 e : {glm::vec3(25, 57.6f, 0), glm::vec3(-10, -120, 15), glm::vec3(80, 179, -30)}) {
    glm::vec3 back = quat_to_euler_degrees(euler_degrees_to_quat(e));
    EXPECT_TRUE(near(back, e, 1e-2f)) << e.x << "," << e.y << "," << e.z << " -> " << back.x << "," << back.y << "," << back.z;
  }
}

TEST(Camera, CameraViewRaysAndProjectionAgree) {
  Transform t = Transform::look_at({100, 2, -50}, {0, 40, -300});
  Camera cam;
  CameraView v = make_camera_view(t, cam, 16.0f / 9.0f);
  EXPECT_TRUE(near(v.ray_direction({0, 0}), t.forward()));
  // A world point projects to some NDC; the ray through that NDC points at it.
  glm::vec3 p(-20, 60, -400);
  glm::vec4 ndc = v.project(p);
  ASSERT_GT(ndc.w, 0.0f);
  EXPECT_TRUE(near(v.ray_direction(glm::vec2(ndc)), glm::normalize(p - t.position), 1e-3f));
  EXPECT_NEAR(linearize_depth(ndc.z, cam.near, cam.far), glm::dot(p - t.position, t.forward()), 0.5f);
  // The top of the screen (ndc y = -1) looks higher than the bottom.
  EXPECT_GT(v.ray_direction({0, -1}).y, v.ray_direction({0, 1}).y);
  EXPECT_LT(v.project(t.position - t.forward() * 10.0f).w, 0.0f);  // behind
}

TEST(Camera, FrustumCullsBoxesBehindAndBeyond) {
  Transform t = Transform::look_at({0, 0, 0}, {0, 0, -1});
  Camera cam{60.0f, 0.5f, 1000.0f};
  CameraView v = make_camera_view(t, cam, 1.0f);
  Frustum f = Frustum::from(v.view_proj);
  auto box = [](glm::vec3 c, float r) {
    Bounds b;
    b.add(c - glm::vec3(r));
    b.add(c + glm::vec3(r));
    return b;
  };
  EXPECT_TRUE(f.intersects(box({0, 0, -100}, 1)));
  EXPECT_FALSE(f.intersects(box({0, 0, 100}, 1)));     // behind
  EXPECT_FALSE(f.intersects(box({0, 0, -2000}, 1)));   // past the far plane
  EXPECT_FALSE(f.intersects(box({500, 0, -100}, 1)));  // off to the side
  EXPECT_TRUE(f.intersects(box({0, 0, -1000}, 5)));    // straddles the far plane
  EXPECT_FALSE(f.intersects(Bounds{}));
}

TEST(Camera, FindCameraByNameAndListTheOthersOnError) {
  ecs::World world;
  for (const char* name : {"ground", "mixed"}) {
    ecs::Entity e = world.create();
    world.emplace<ecs::Name>(e, ecs::Name{name});
    world.emplace<Transform>(e, Transform::look_at({0, 2, 0}, {0, 2, -1}));
    world.emplace<Camera>(e);
  }
  ecs::Entity not_a_camera = world.create();
  world.emplace<ecs::Name>(not_a_camera, ecs::Name{"sun"});
  ecs::Entity e = find_camera(world, "mixed");
  EXPECT_EQ(world.get<ecs::Name>(e).value, "mixed");
  EXPECT_EQ(camera_names(world), (std::vector<std::string>{"ground", "mixed"}));
  expect_error([&] { find_camera(world, "sun"); }, {"no camera named \"sun\"", "ground, mixed"});
}
