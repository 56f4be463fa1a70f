#pragma once
// Internals shared by the headless (application.cpp) and windowed (windowed.cpp) loops.
#include <string>

#include "engine/app/fixed_step.h"
#include "engine/app/fly_camera.h"
#include "engine/app/run_options.h"
#include "engine/app/run_stats.h"
#include "engine/app/simulation.h"
#include "engine/render/dynamic_resolution.h"
#include "engine/render/frame_snapshot.h"

namespace cumulo::gpu {
class Context;
}
namespace cumulo::render {
struct CompiledGraph;
class FrameRenderer;
}

namespace cumulo::app::detail {

struct RunContext {
  RunOptions opt;
  Modules modules;
  Simulation sim;
  ecs::Entity camera;
  FixedStepClock clock;
  RunStats stats;
  render::DynamicResolution resolution;  // --dynamic-resolution (configure_resolution sets it up)
  RunContext(const RunOptions& o, const SimulationDesc& d) : opt(o), modules(d.modules), sim(d), clock(o.sim_hz) {}
};

// The frame renderer of a run with every module's passes added (create_gpu runs here).
void add_module_features(RunContext& rc, render::FrameRenderer& renderer);
// Extract phase + snapshot of the camera entity at w x h, with every module's extension.
render::FrameSnapshot extract(RunContext& rc, uint32_t w, uint32_t h, uint64_t frame);
// Dynamic resolution from the flags and the device: on by default in a window, off headless; the
// budget scale the device's default unless --budget-scale.
void configure_resolution(RunContext& rc, const gpu::Context& ctx, bool windowed);
// The scale the next frame renders at: --resolution-scale, else the dynamic one (1 when off).
float next_resolution_scale(const RunContext& rc);
// A completed frame's GPU pass timings (their sum; `fallback_ms` when there are none, ignored when NaN) feed
// the dynamic resolution.
void feed_resolution(RunContext& rc, const std::vector<std::pair<std::string, double>>& timings, double fallback_ms);
// Writes --stats (if asked).
void write_stats(RunContext& rc, gpu::Context& ctx, uint32_t w, uint32_t h);
// Writes --dump-graph: Graphviz when the path ends in .dot, text otherwise.
void write_graph_dump(const std::string& path, const render::CompiledGraph& graph);
// Puts the fly camera's pose into the camera entity's Transform.
void apply_fly_camera(ecs::World& world, ecs::Entity camera, const FlyCamera& fly);
// The fly camera starting at the camera entity's pose.
FlyCamera fly_camera_from(const ecs::World& world, ecs::Entity camera);

// Windowed loop (windowed.cpp). Throws WindowUnavailable when no window can be opened.
int run_windowed(RunContext& rc);

}  // namespace cumulo::app::detail
