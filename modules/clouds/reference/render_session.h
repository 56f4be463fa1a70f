#pragma once
// A level rendered frame by frame with the simulation held still (cumulo reference, cumulo fidelity): the
// clouds module's renderer on a headless Vulkan device, a camera placed by name or by pose, the time of
// day set, and each frame's tonemapped output for a PNG. Nothing moves between frames unless the caller
// steps the simulation, so a real-time image can be averaged and a reference accumulated on the same scene.
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "engine/app/simulation.h"
#include "engine/gpu/readback.h"
#include "engine/render/budget_mode.h"

namespace cumulo::gpu {
class Context;
}
namespace cumulo::clouds {

class CloudsModule;

struct RenderSessionDesc {
  std::string level;
  uint32_t width = 160, height = 90;
  std::optional<float> time_of_day;
  cumulo::render::BudgetMode mode = cumulo::render::BudgetMode::Hz30;
};

class RenderSession {
 public:
  // Loads the level (throws cumulo::Error naming the file) and creates the device and the renderer with
  // `module` (not owned; its options are already parsed).
  RenderSession(const RenderSessionDesc& desc, CloudsModule& module);
  ~RenderSession();

  app::Simulation& sim() { return *sim_; }
  gpu::Context& ctx() { return *ctx_; }
  uint32_t width() const { return desc_.width; }
  uint32_t height() const { return desc_.height; }
  // The named camera entity (throws naming the level when there is none of that name).
  ecs::Entity camera(const std::string& name);
  // Puts `camera` at `position` looking at `target` with the vertical field of view.
  void place_camera(ecs::Entity camera, glm::vec3 position, glm::vec3 target, float fov_y_deg);
  void set_time_of_day(float hours);
  float time_of_day() const;
  // One frame from `camera` (the simulation is not advanced); waits for the device.
  void render(ecs::Entity camera);
  // The last frame's tonemapped output.
  gpu::Rgba8Image screenshot();

 private:
  struct Gpu;
  RenderSessionDesc desc_;
  CloudsModule& module_;
  std::unique_ptr<app::Simulation> sim_;
  std::unique_ptr<gpu::Context> ctx_;
  std::unique_ptr<Gpu> gpu_;
  uint64_t frame_index_ = 0;
};

}  // namespace cumulo::clouds
