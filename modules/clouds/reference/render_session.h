#pragma once
// A level rendered frame by frame with the simulation held still (cumulo reference, cumulo fidelity): the
// engine's headless session (engine/app/headless_session.h) with every module, a camera placed by name or
// by pose, the time of day set, and each frame's tonemapped output for a PNG. Nothing moves between frames unless the caller
// steps the simulation, so a real-time image can be averaged and a reference accumulated on the same scene.
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "engine/app/headless_session.h"
#include "engine/app/simulation.h"
#include "modules/clouds/options/clouds_run.h"
#include "engine/gpu/readback.h"
#include "engine/render/budget_mode.h"

namespace cumulo::gpu {
class Context;
}
namespace cumulo::clouds {

struct RenderSessionDesc {
  std::string level;
  uint32_t width = 160, height = 90;
  std::optional<float> time_of_day;
  cumulo::render::BudgetMode mode = cumulo::render::BudgetMode::Hz30;
};

class RenderSession {
 public:
  // Loads the level (throws cumulo::Error naming the file) and creates the device and the renderer with
  // every module of `run` (their options already parsed).
  RenderSession(const RenderSessionDesc& desc, const CloudsRun& run);

  app::Simulation& sim() { return session_->sim(); }
  gpu::Context& ctx() { return session_->ctx(); }
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
  RenderSessionDesc desc_;
  std::unique_ptr<app::HeadlessSession> session_;
};

}  // namespace cumulo::clouds
