#pragma once
// Free-fly / flight camera for windowed runs: WASD moves in the view plane, Q/E down/up (world),
// mouse look while the right button is held or the cursor is captured (Tab toggles capture), Shift
// flies 8x faster, Ctrl 8x slower, the wheel scales the base speed. Plain data plus a pure update,
// so it is tested without a window.
#include <glm/glm.hpp>

#include "engine/platform/input.h"

namespace cumulo::app {

struct FlyCamera {
  glm::vec3 position{0.0f};
  float yaw = 0.0f;    // radians; 0 looks down -Z, positive turns toward -X (left, right-handed Y-up)
  float pitch = 0.0f;  // radians; positive looks up, clamped to +-89 deg
  float speed = 30.0f;              // m/s (a 4 km level; flight needs far more with Shift)
  float mouse_sensitivity = 0.0025f;  // radians per pixel
};

// Y-up, right-handed; the view looks along forward().
glm::vec3 fly_forward(const FlyCamera& c);
glm::vec3 fly_right(const FlyCamera& c);
glm::mat4 fly_view_matrix(const FlyCamera& c);
glm::quat fly_rotation(const FlyCamera& c);
// Builds yaw/pitch from a world-space direction (used to start from a level camera's orientation).
void fly_look_along(FlyCamera& c, glm::vec3 direction);

// Advances the camera by dt seconds of input. Returns true when it moved or turned.
bool update_fly_camera(FlyCamera& c, const platform::InputState& input, float dt);

}  // namespace cumulo::app
