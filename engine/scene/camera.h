#pragma once
// Camera math for the Vulkan renderer, and named-camera lookup in a World.
//
// [index]  perspective  view_matrix  CameraView / make_camera_view  linearize_depth  Frustum  find_camera
//
// Conventions (the renderer and the cloud passes rely on these; change them together):
// - View space is right-handed, camera looking down -Z, +Y up.
// - Clip space is Vulkan's: x right, y DOWN (the projection flips Y, so use a normal positive-height
//   viewport), depth in [0, 1].
// - Reversed-Z with a finite far plane: depth 1 at the near plane, 0 at the far plane. Clear depth to 0.0
//   and test with VK_COMPARE_OP_GREATER_OR_EQUAL. Reversed-Z keeps float depth precise from 0.1 m to 50 km.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/world.h"
#include "engine/scene/components.h"
#include "engine/scene/model.h"

namespace cumulo::scene {

// Reversed-Z Vulkan perspective (see the conventions above). fov_y in radians.
glm::mat4 perspective(float fov_y, float aspect, float near, float far);
// World -> view: the inverse of the rigid part (position, rotation) of `t`; scale is ignored.
glm::mat4 view_matrix(const Transform& t);
// View-space distance along -Z for a reversed-Z depth value `d` in [0, 1] written with (near, far).
float linearize_depth(float d, float near, float far);

// Everything a pass needs to know about the camera of a frame.
struct CameraView {
  glm::mat4 view{1.0f}, proj{1.0f}, view_proj{1.0f};
  glm::mat4 inv_view{1.0f}, inv_proj{1.0f}, inv_view_proj{1.0f};
  glm::vec3 position{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  float fov_y = 1.0f;  // radians
  float aspect = 1.0f;
  float near = 0.1f, far = 50000.0f;

  // World-space unit direction of the ray through a pixel centre; ndc in [-1, 1]^2, y down (Vulkan).
  glm::vec3 ray_direction(const glm::vec2& ndc) const;
  // Vulkan NDC (x, y in [-1, 1], y down; z = reversed depth) of a world-space point; w <= 0 means behind.
  glm::vec4 project(const glm::vec3& world) const;
};

CameraView make_camera_view(const Transform& t, const Camera& c, float aspect);

// The six planes of a view-projection (normals point inward); used for culling instances by their bounds.
struct Frustum {
  std::array<glm::vec4, 6> planes{};  // xyz = normal, w = distance: inside when dot(n, p) + w >= 0
  static Frustum from(const glm::mat4& view_proj);
  bool intersects(const Bounds& world_bounds) const;  // conservative: may say yes for a box just outside
};

// The entity named `name` that has a Camera and a Transform. Throws cumulo::Error listing the cameras
// there are when none matches: `no camera named "x" (the level has: ground, mixed, immersed)`.
ecs::Entity find_camera(const ecs::World& world, std::string_view name);
// The first entity (in entity order: the level file's) with a Camera and a Transform, named or not; null when none.
ecs::Entity first_camera(const ecs::World& world);
// The names of every entity with a Camera, in entity order.
std::vector<std::string> camera_names(const ecs::World& world);

}  // namespace cumulo::scene
