#pragma once
// The read-only snapshot the renderer draws from (DESIGN.md "The frame": simulation -> extract ->
// render). Extraction copies what a frame needs out of the ECS world; from then on the renderer never
// touches the world, and the simulation never touches Vulkan. Models are shared (immutable) CPU data.
// Modules add their own per-frame data as typed extensions (the engine knows nothing of clouds), and
// may replace the stand-in sky lighting (the atmosphere does).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <typeindex>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/error.h"
#include "engine/ecs/world.h"
#include "engine/render/budget_mode.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"

namespace cumulo::render {

struct ModelDraw {
  std::shared_ptr<const scene::Model> model;
  glm::mat4 world{1.0f};  // entity transform; the model's own instance matrices apply inside it
};

// The light the scene passes (and modules) use, in the renderer's units (exposure 1 maps the noon sun's
// radiance of about 3 to a bright, unclipped white). extract_frame fills it from the stand-in sky model
// (sky_model.h); a module's extract may replace it.
// A short-lived light on the geometry (FRAME_MAX_POINT_LIGHTS of them reach the geometry pass; a module's
// extract may add them, e.g. a lightning discharge lighting the terrain).
struct PointLight {
  glm::vec3 position{0.0f};
  float reach = 1000.0f;      // m: the light fades smoothly to 0 there
  glm::vec3 color{0.0f};      // radiance scale of a white Lambertian surface facing it at 500 m
};

struct SceneLighting {
  glm::vec3 sun_radiance{0.0f};   // reaching the ground (after the atmosphere)
  float ambient = 0.0f;           // scale of the hemispheric ambient term
  glm::vec3 sky_zenith{0.0f}, sky_horizon{0.0f}, ground{0.0f};
  // The sky's mean radiance over the upper hemisphere (per solid angle; the atmosphere fills it, 0: not known).
  // About half of 0.5 (zenith + horizon) by day, and neutral where that is warm at a low sun: the horizon is
  // the sky's brightest band and holds the sun's glow.
  glm::vec3 sky_mean{0.0f};
  // The sky's irradiance on a horizontal surface over pi: the radiance a white Lambertian ground reflects of the sky
  // (the upper hemisphere's radiance weighted by the cosine; 0: not known). Below sky_mean where the sky is brightest
  // near the horizon, as at a low sun: a ground sees that band at a grazing angle.
  glm::vec3 sky_irradiance{0.0f};
  float fog_density = 0.0f;       // 1/m at sea level
  float fog_falloff = 0.0f;       // 1/m (exponential height falloff)
  std::string source = "stand-in";  // who filled it (stats, debugging)
  std::vector<PointLight> point_lights;  // the first FRAME_MAX_POINT_LIGHTS reach the geometry
  // Toward the key light whose radiance sun_radiance is: the sun, or at night the moon; zero: the sun's
  // direction (snapshot.sun.direction).
  glm::vec3 light_direction{0.0f};
  // The scene's exposure meter (times the renderer's exposure): 1 by day, up to 32 in a moonlit night,
  // so a night reads as dark but not black (the eye adapts; the atmosphere sets it from its light level).
  float exposure = 1.0f;
  // The weather's haze as a multiplier of the atmosphere's Mie (aerosol) density: the LUTs and the
  // aerial perspective scatter more in haze (a module's extract sets it; 1: the preset's air).
  float mie_scale = 1.0f;
};

// Per-frame data of modules, one value per type:
//   snapshot.extensions.set(CloudFrame{...});            // in the module's extract()
//   if (auto* c = snapshot.extensions.find<CloudFrame>()) ...   // in its add_passes()
class SnapshotExtensions {
 public:
  template <class T>
  T& set(T value) {
    auto p = std::make_shared<T>(std::move(value));
    T& ref = *p;
    for (auto& [type, v] : items_)
      if (type == std::type_index(typeid(T))) {
        v = std::move(p);
        return ref;
      }
    items_.emplace_back(std::type_index(typeid(T)), std::move(p));
    return ref;
  }
  template <class T>
  const T* find() const {
    for (auto& [type, v] : items_)
      if (type == std::type_index(typeid(T))) return static_cast<const T*>(v.get());
    return nullptr;
  }
  template <class T>
  const T& get() const {
    if (const T* p = find<T>()) return *p;
    fail("frame snapshot: no extension of type %s", typeid(T).name());
  }
  size_t size() const { return items_.size(); }

 private:
  // shared_ptr<const void> keeps copies of a snapshot cheap; values are immutable once extracted.
  std::vector<std::pair<std::type_index, std::shared_ptr<const void>>> items_;
};

struct FrameSnapshot {
  uint32_t width = 0, height = 0;
  BudgetMode mode = BudgetMode::Hz30;
  // The passes that can scale (the cloud march, the 2.5D sky) render at this fraction of the output's
  // width and height (dynamic_resolution.h; 1 unless the run's dynamic resolution or --resolution-scale set it).
  float resolution_scale = 1.0f;
  uint64_t frame_index = 0;
  double sim_time = 0.0;
  uint64_t sim_step = 0;
  std::string camera_name;
  scene::CameraView camera;
  scene::SunLight sun;            // the one sun (scene::find_sun decides which TimeOfDay/Sun count)
  float time_of_day_hours = 12.0f;
  SceneLighting lighting;
  std::vector<ModelDraw> models;
  std::optional<scene::Ocean> ocean;
  SnapshotExtensions extensions;
};

// Reads the camera entity (Camera + Transform), the sun (scene::find_sun), every ModelRef with a
// Transform, and fills the stand-in lighting. Throws cumulo::Error naming the camera entity if it lacks
// a Camera or Transform.
FrameSnapshot extract_frame(const ecs::World& world, ecs::Entity camera, uint32_t width, uint32_t height);

}  // namespace cumulo::render
