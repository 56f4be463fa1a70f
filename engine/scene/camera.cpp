#include "engine/scene/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/error.h"
#include "engine/core/message.h"

namespace cumulo::scene {

glm::mat4 perspective(float fov_y, float aspect, float near, float far) {
  // Reversed-Z, right-handed, Vulkan clip space: z_clip / w_clip = 1 at -near, 0 at -far.
  //   depth(t) = near * (far - t) / (t * (far - near)) for a view distance t along -Z.
  float f = 1.0f / std::tan(0.5f * fov_y);
  glm::mat4 m(0.0f);
  m[0][0] = f / aspect;
  m[1][1] = -f;  // Vulkan's clip-space y points down
  m[2][2] = near / (far - near);
  m[2][3] = -1.0f;
  m[3][2] = far * near / (far - near);
  return m;
}

float linearize_depth(float d, float near, float far) {
  // Inverse of depth(t) above.
  return far * near / ((far - near) * d + near);
}

glm::mat4 view_matrix(const Transform& t) {
  glm::mat4 inv_rot = glm::mat4_cast(glm::conjugate(glm::normalize(t.rotation)));
  return inv_rot * glm::translate(glm::mat4(1.0f), -t.position);
}

glm::vec3 CameraView::ray_direction(const glm::vec2& ndc) const {
  // Unproject a point on the near plane (depth 1 in reversed-Z) and one farther along the same pixel ray.
  glm::vec4 a = inv_view_proj * glm::vec4(ndc, 1.0f, 1.0f);
  glm::vec4 b = inv_view_proj * glm::vec4(ndc, 0.5f, 1.0f);
  return glm::normalize(glm::vec3(b) / b.w - glm::vec3(a) / a.w);
}

glm::vec4 CameraView::project(const glm::vec3& world) const {
  glm::vec4 c = view_proj * glm::vec4(world, 1.0f);
  if (c.w <= 0.0f) return glm::vec4(0.0f, 0.0f, 0.0f, c.w);
  return glm::vec4(glm::vec3(c) / c.w, c.w);
}

CameraView make_camera_view(const Transform& t, const Camera& c, float aspect) {
  CameraView v;
  v.position = t.position;
  v.forward = t.forward();
  v.fov_y = glm::radians(c.fov_y_deg);
  v.aspect = aspect;
  v.near = c.near;
  v.far = c.far;
  v.view = view_matrix(t);
  v.proj = perspective(v.fov_y, aspect, c.near, c.far);
  v.view_proj = v.proj * v.view;
  v.inv_view = glm::inverse(v.view);
  v.inv_proj = glm::inverse(v.proj);
  v.inv_view_proj = glm::inverse(v.view_proj);
  return v;
}

Frustum Frustum::from(const glm::mat4& m) {
  // Gribb-Hartmann plane extraction on the rows of the matrix, for clip space -w<=x,y<=w, 0<=z<=w.
  auto row = [&](int r) { return glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
  Frustum f;
  f.planes[0] = row(3) + row(0);  // left
  f.planes[1] = row(3) - row(0);  // right
  f.planes[2] = row(3) + row(1);  // y >= -w
  f.planes[3] = row(3) - row(1);  // y <= w
  f.planes[4] = row(2);           // z >= 0: the far plane under reversed-Z
  f.planes[5] = row(3) - row(2);  // z <= w: the near plane under reversed-Z
  for (auto& p : f.planes) p /= glm::length(glm::vec3(p));
  return f;
}

bool Frustum::intersects(const Bounds& b) const {
  if (b.empty()) return false;
  for (const auto& p : planes) {
    // The box corner farthest along the plane normal; if even it is outside, the whole box is.
    glm::vec3 corner(p.x >= 0 ? b.max.x : b.min.x, p.y >= 0 ? b.max.y : b.min.y, p.z >= 0 ? b.max.z : b.min.z);
    if (glm::dot(glm::vec3(p), corner) + p.w < 0.0f) return false;
  }
  return true;
}

std::vector<std::string> camera_names(const ecs::World& world) {
  std::vector<std::string> names;
  world.each_entity([&](ecs::Entity e) {
    if (!world.has<Camera>(e)) return;
    const auto* n = world.try_get<ecs::Name>(e);
    names.push_back(n ? n->value : "<unnamed>");
  });
  return names;
}

ecs::Entity first_camera(const ecs::World& world) {
  ecs::Entity found = ecs::Entity::null();
  world.each_entity([&](ecs::Entity e) {
    if (found.is_null() && world.has<Camera>(e) && world.has<Transform>(e)) found = e;
  });
  return found;
}

ecs::Entity find_camera(const ecs::World& world, std::string_view name) {
  ecs::Entity found = ecs::Entity::null();
  world.each_entity([&](ecs::Entity e) {
    if (!found.is_null() || !world.has<Camera>(e) || !world.has<Transform>(e)) return;
    const auto* n = world.try_get<ecs::Name>(e);
    if (n && n->value == name) found = e;
  });
  if (found.is_null()) {
    std::string list;
    for (auto& n : camera_names(world)) list += (list.empty() ? "" : ", ") + n;
    throw Error(strf("no camera named %s (the level has: %s)", quote(name).c_str(),
                     list.empty() ? "no cameras" : clip(list, 300).c_str()));
  }
  return found;
}

}  // namespace cumulo::scene
