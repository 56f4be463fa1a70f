#pragma once
// One headless session of the engine: a level's simulation with every module (components, systems,
// level hooks), a headless Vulkan device, the frame renderer with every module's passes, and an offscreen
// RGBA8 output. `cumulo run --headless`, `cumulo bench`, `cumulo reference` and `cumulo fidelity` all
// render through it, so a frame is made the same way everywhere: the Extract phase, the camera's snapshot
// at the simulation's time and step, every module's extension, one frame in flight.
//
//   HeadlessSession s({sim_desc, 320, 180});
//   s.sim().step(4);
//   s.render(s.sim().camera("ground"), render::BudgetMode::Hz30);
//   gpu::write_png("out.png", s.screenshot());
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/app/simulation.h"
#include "engine/gpu/readback.h"
#include "engine/render/budget_mode.h"
#include "engine/render/frame_snapshot.h"

namespace cumulo::gpu {
class Context;
}
namespace cumulo::render {
class FrameRenderer;
}

namespace cumulo::app {

struct HeadlessSessionDesc {
  SimulationDesc sim;
  uint32_t width = 320, height = 180;
  bool aerial_lut = true;  // --aerial-perspective lut|fog
};

class HeadlessSession {
 public:
  // Loads the level (throws cumulo::Error naming the file and place), then creates the device, the
  // renderer (every module's create_gpu) and the output.
  explicit HeadlessSession(const HeadlessSessionDesc& desc);
  // The same on a simulation the caller owns and has set up (`cumulo run`: its viewer, events, recording).
  HeadlessSession(Simulation& sim, const Modules& modules, uint32_t width, uint32_t height, bool aerial_lut = true);
  ~HeadlessSession();
  HeadlessSession(const HeadlessSession&) = delete;
  HeadlessSession& operator=(const HeadlessSession&) = delete;

  Simulation& sim() { return *sim_; }
  gpu::Context& ctx() { return *ctx_; }
  render::FrameRenderer& renderer();
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  uint64_t frames() const { return frame_index_; }  // rendered so far

  // The next frame's snapshot: the Extract phase, then `camera` at the simulation's time and step in
  // `mode`, with every module's extension.
  render::FrameSnapshot extract(ecs::Entity camera, render::BudgetMode mode);
  // Records and submits `snapshot` as the next frame (the simulation is not advanced); wait_frame waits
  // for it (one frame in flight: the next frame rewrites the same output image). render does both.
  void submit(render::FrameSnapshot& snapshot);
  void wait_frame();
  void render(render::FrameSnapshot& snapshot);
  void render(ecs::Entity camera, render::BudgetMode mode);
  // The last frame's GPU pass timings and its tonemapped output.
  std::vector<std::pair<std::string, double>> pass_timings() const;
  gpu::Rgba8Image screenshot();
  // Waits for the device and reports its validation errors: 0, or logs the last one and returns 3 (the
  // commands' exit code).
  int finish();

 private:
  struct Gpu;
  void create_gpu(bool aerial_lut);
  Modules modules_;
  std::unique_ptr<Simulation> owned_sim_;
  Simulation* sim_ = nullptr;
  uint32_t width_, height_;
  std::unique_ptr<gpu::Context> ctx_;
  std::unique_ptr<Gpu> gpu_;
  uint64_t frame_index_ = 0;
};

}  // namespace cumulo::app
