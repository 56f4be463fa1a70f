#include "engine/app/fly_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

namespace cumulo::app {

using platform::Key;

glm::vec3 fly_forward(const FlyCamera& c) {
  float cp = std::cos(c.pitch);
  return glm::normalize(glm::vec3(-std::sin(c.yaw) * cp, std::sin(c.pitch), -std::cos(c.yaw) * cp));
}

glm::vec3 fly_right(const FlyCamera& c) { return glm::normalize(glm::cross(fly_forward(c), glm::vec3(0, 1, 0))); }

glm::mat4 fly_view_matrix(const FlyCamera& c) {
  return glm::lookAt(c.position, c.position + fly_forward(c), glm::vec3(0, 1, 0));
}

glm::quat fly_rotation(const FlyCamera& c) {
  return glm::angleAxis(c.yaw, glm::vec3(0, 1, 0)) * glm::angleAxis(c.pitch, glm::vec3(1, 0, 0));
}

void fly_look_along(FlyCamera& c, glm::vec3 d) {
  if (glm::length(d) < 1e-6f) return;
  d = glm::normalize(d);
  c.pitch = std::asin(std::clamp(d.y, -1.0f, 1.0f));
  c.yaw = std::atan2(-d.x, -d.z);
}

bool update_fly_camera(FlyCamera& c, const platform::InputState& in, float dt) {
  bool changed = false;
  if (in.scroll != 0.0) c.speed = std::clamp(c.speed * std::pow(1.2f, static_cast<float>(in.scroll)), 0.5f, 5000.0f);
  if (in.cursor_captured || in.is_down(platform::MouseButton::Right)) {
    if (in.mouse_dx != 0.0 || in.mouse_dy != 0.0) {
      c.yaw -= static_cast<float>(in.mouse_dx) * c.mouse_sensitivity;
      c.pitch -= static_cast<float>(in.mouse_dy) * c.mouse_sensitivity;
      c.pitch = std::clamp(c.pitch, glm::radians(-89.0f), glm::radians(89.0f));
      c.yaw = std::remainder(c.yaw, 2.0f * glm::pi<float>());
      changed = true;
    }
  }
  glm::vec3 f = fly_forward(c), r = fly_right(c), move(0.0f);
  if (in.is_down(Key::W)) move += f;
  if (in.is_down(Key::S)) move -= f;
  if (in.is_down(Key::D)) move += r;
  if (in.is_down(Key::A)) move -= r;
  if (in.is_down(Key::E) || in.is_down(Key::Space)) move.y += 1.0f;
  if (in.is_down(Key::Q)) move.y -= 1.0f;
  if (glm::length(move) > 0.0f) {
    float speed = c.speed;
    if (in.is_down(Key::LeftShift)) speed *= 8.0f;
    if (in.is_down(Key::LeftControl)) speed /= 8.0f;
    c.position += glm::normalize(move) * speed * dt;
    changed = true;
  }
  return changed;
}

}  // namespace cumulo::app
