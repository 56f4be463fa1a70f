#pragma once
// The read-only snapshot the renderer draws from (DESIGN.md "The frame": simulation -> extract ->
// render). Extraction copies what a frame needs out of the ECS world; from then on the renderer never
// touches the world, and the simulation never touches Vulkan. Models are shared (immutable) CPU data.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/ecs/world.h"
#include "engine/render/budget_mode.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"

namespace cumulo::render {

struct ModelDraw {
  std::shared_ptr<const scene::Model> model;
  glm::mat4 world{1.0f};  // entity transform; the model's own instance matrices apply inside it
};

struct SunLight {
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // unit, toward the sun
  glm::vec3 color{1.0f};                  // Sun::color x atmospheric transmittance (linear)
  float illuminance = 1.0f;
  float elevation_deg = 90.0f;
  float time_of_day_hours = 12.0f;
};

struct FrameSnapshot {
  uint32_t width = 0, height = 0;
  BudgetMode mode = BudgetMode::Hz30;
  uint64_t frame_index = 0;
  double sim_time = 0.0;
  uint64_t sim_step = 0;
  std::string camera_name;
  scene::CameraView camera;
  SunLight sun;
  std::vector<ModelDraw> models;
  std::optional<scene::Ocean> ocean;
};

// Reads the camera entity (Camera + Transform), the TimeOfDay/Sun (a world resource, or the first
// entity that has them) and every ModelRef with a Transform. Throws cumulo::Error if the camera
// entity lacks a Camera or Transform.
FrameSnapshot extract_frame(const ecs::World& world, ecs::Entity camera, uint32_t width, uint32_t height);

}  // namespace cumulo::render
