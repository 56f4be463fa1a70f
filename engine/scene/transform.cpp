#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/scene/components.h"

namespace cumulo::scene {

glm::mat4 Transform::matrix() const {
  glm::mat4 m = glm::translate(glm::mat4(1.0f), position) * glm::mat4_cast(rotation);
  return glm::scale(m, scale);
}

glm::vec3 Transform::forward() const { return rotation * glm::vec3(0.0f, 0.0f, -1.0f); }
glm::vec3 Transform::up() const { return rotation * glm::vec3(0.0f, 1.0f, 0.0f); }
glm::vec3 Transform::right() const { return rotation * glm::vec3(1.0f, 0.0f, 0.0f); }

Transform Transform::look_at(const glm::vec3& position, const glm::vec3& target, const glm::vec3& up) {
  Transform t;
  t.position = position;
  glm::vec3 f = target - position;
  float len = glm::length(f);
  if (!(len > 1e-6f)) return t;  // target on the position: keep the identity orientation
  f /= len;
  glm::vec3 u = glm::normalize(up);
  // Looking straight along `up` leaves the roll undefined: pick -Z (north) as the screen's up instead.
  if (std::abs(glm::dot(f, u)) > 0.9999f) u = std::abs(f.z) < 0.9f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  glm::vec3 r = glm::normalize(glm::cross(f, u));
  glm::vec3 true_up = glm::cross(r, f);
  glm::mat3 basis(r, true_up, -f);  // columns: local X, Y, Z in world space
  t.rotation = glm::normalize(glm::quat_cast(basis));
  return t;
}

glm::quat euler_degrees_to_quat(const glm::vec3& pyr) {
  glm::quat yaw = glm::angleAxis(glm::radians(pyr.y), glm::vec3(0, 1, 0));
  glm::quat pitch = glm::angleAxis(glm::radians(pyr.x), glm::vec3(1, 0, 0));
  glm::quat roll = glm::angleAxis(glm::radians(pyr.z), glm::vec3(0, 0, 1));
  return glm::normalize(yaw * pitch * roll);
}

glm::vec3 quat_to_euler_degrees(const glm::quat& q) {
  // R = Ry(yaw) * Rx(pitch) * Rz(roll). Its third column is R*(0,0,1) = (sy*cp, -sp, cy*cp) and its
  // second row is (cp*sr, cp*cr, -sp) in columns 0,1: solve for the three angles from those.
  glm::mat3 m = glm::mat3_cast(glm::normalize(q));
  float sp = -m[2][1];
  sp = glm::clamp(sp, -1.0f, 1.0f);
  float pitch = std::asin(sp);
  float yaw, roll;
  if (std::abs(sp) < 0.9999f) {
    yaw = std::atan2(m[2][0], m[2][2]);
    roll = std::atan2(m[0][1], m[1][1]);
  } else {  // gimbal lock: fold the roll into the yaw
    yaw = std::atan2(-m[0][2], m[0][0]);
    roll = 0.0f;
  }
  return glm::degrees(glm::vec3(pitch, yaw, roll));
}

}  // namespace cumulo::scene
