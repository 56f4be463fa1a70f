#pragma once
// Scene components: plain structs a level attaches to entities. Registered for JSON by
// scene::register_components() (see serialization.h), which documents each JSON form.
//
// [index]  Transform  Camera  ModelRef  TimeOfDay  Sun  Ocean
//
// Axes (the whole engine): metres, right-handed, +Y up, +X east, -Z north, sea level at y = 0.
// Cameras and lights look down their local -Z (glTF's convention).
#include <filesystem>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace cumulo::scene {

struct Model;

struct Transform {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z (glm order); identity looks down -Z
  glm::vec3 scale{1.0f};

  glm::mat4 matrix() const;       // T * R * S
  glm::vec3 forward() const;      // rotation * (0, 0, -1)
  glm::vec3 up() const;           // rotation * (0, 1, 0)
  glm::vec3 right() const;        // rotation * (1, 0, 0)
  // A transform at `position` whose -Z looks at `target` with +Y as close to `up` as possible.
  static Transform look_at(const glm::vec3& position, const glm::vec3& target, const glm::vec3& up = {0, 1, 0});
};

// Rotation from Euler angles in degrees: yaw about +Y, then pitch about the new +X, then roll about the new +Z
// (q = yaw * pitch * roll). Pitch > 0 looks up; yaw > 0 turns left (counter-clockwise seen from above).
glm::quat euler_degrees_to_quat(const glm::vec3& pitch_yaw_roll_deg);
glm::vec3 quat_to_euler_degrees(const glm::quat& q);  // inverse of the above (pitch in [-90, 90])

// A perspective camera; the entity's Name names it ("ground", "mixed", "immersed"), its Transform places it.
struct Camera {
  float fov_y_deg = 60.0f;  // vertical field of view
  float near = 0.1f;        // metres; reversed-Z keeps precision at 0.1 m with a 50 km far plane
  float far = 50000.0f;     // metres; the sample ocean reaches 20 km from the origin
};

// A glTF model drawn at the entity's Transform. `path` is as written in the level (relative to the level
// file); load_level() fills `resolved` and `model` (shared between entities that name the same file).
struct ModelRef {
  std::string path;
  std::filesystem::path resolved;
  std::shared_ptr<const Model> model;
  bool cast_shadows = true;
};

// Time of day and place on Earth; sun_direction() (sun.h) turns it into the direction toward the sun.
// Defaults: the Burning Shores' Los Angeles (34.05 N), late August, late afternoon light.
struct TimeOfDay {
  float hours = 16.5f;            // local solar time, [0, 24)
  int day_of_year = 240;          // 1..365, sets the solar declination
  float latitude_deg = 34.05f;    // -90..90, north positive
  float north_deg = 0.0f;         // where true north lies: degrees clockwise (seen from above) from world -Z
  float hours_per_second = 0.0f;  // simulation speed of the day cycle (0 = fixed time)
};

// The directional light the time of day drives.
struct Sun {
  glm::vec3 color{1.0f, 1.0f, 1.0f};  // linear RGB tint, multiplied with sun_transmittance()
  float illuminance = 1.0f;           // relative intensity (the renderer's exposure maps it)
};

// An infinite-looking sea plane (the sample terrain also carries a 40 km ocean quad at this height).
struct Ocean {
  float sea_level = 0.0f;                  // metres
  glm::vec3 color{0.02f, 0.12f, 0.20f};    // linear RGB of deep water
};

}  // namespace cumulo::scene
