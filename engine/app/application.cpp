#include "engine/app/application.h"

#include <algorithm>
#include <cstdio>

#include "engine/app/detail/run_context.h"
#include "engine/app/frame_output.h"
#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/readback.h"
#include "engine/platform/window.h"
#include "engine/render/frame_renderer.h"

namespace cumulo::app {
namespace {

using detail::RunContext;

// Headless: no window, offscreen RGBA8 output, exactly 1/mode s of simulation per frame.
int run_headless(RunContext& rc) {
  const RunOptions& o = rc.opt;
  gpu::Context ctx(gpu::ContextDesc{});
  LOG_INFO("device: %s (%s)", ctx.info().name.c_str(), ctx.info().driver_info.c_str());
  render::FrameRenderer renderer(ctx);
  detail::add_module_features(rc, renderer);
  OffscreenOutput output(ctx, o.width, o.height);
  gpu::FrameRing ring(ctx, 1);

  uint32_t frames = std::max(1u, o.frames);
  for (uint32_t f = 1; f <= frames; ++f) {
    Stopwatch cpu;
    uint32_t steps = rc.clock.steps_for_fixed_frame(f, uint32_t(render::budget_hz(o.mode)));
    rc.sim.step(steps);
    rc.clock.on_steps_run(steps);
    render::FrameSnapshot snap = detail::extract(rc, o.width, o.height, f);
    gpu::Frame& fr = ring.begin();
    renderer.record_frame(fr.cmd, snap, output.target(), fr.slot);
    ring.submit(fr);
    rc.stats.add_cpu_frame_ms(cpu.ms());
    ring.wait_all();  // one frame in flight: the next frame rewrites the same output image
    output.after_frame();
    rc.stats.add_gpu_frame(renderer.pass_timings());
    if (f == 1 && !o.dump_graph.empty()) detail::write_graph_dump(o.dump_graph, renderer.last_compiled());
  }
  rc.stats.set_frames(frames);
  if (!o.screenshot.empty()) {
    gpu::write_png(o.screenshot, gpu::read_image_rgba8(ctx, output.image()));
    std::printf("cumulo: wrote screenshot %s\n", o.screenshot.c_str());
  }
  detail::write_stats(rc, ctx, o.width, o.height);
  if (ctx.validation_errors() > 0) {
    LOG_ERROR("%u Vulkan validation errors (last: %s)", ctx.validation_errors(), ctx.last_validation_message().c_str());
    return 3;
  }
  return 0;
}

}  // namespace

int run_level(const RunOptions& options, const Modules& modules) {
  RunOptions o = options;
  bool headless = o.headless;
  if (!headless && !platform::display_available()) {
    std::printf("cumulo: no display (DISPLAY and WAYLAND_DISPLAY are unset): running headless\n");
    headless = true;
  }
  if (headless && o.frames == 0) o.frames = kDefaultHeadlessFrames;

  SimulationDesc sd;
  sd.level = o.level;
  sd.seed = o.seed;
  sd.sim_hz = o.sim_hz;
  sd.time_of_day = o.time_of_day;
  sd.modules = modules;
  RunContext rc(o, sd);
  rc.camera = rc.sim.camera(o.camera);
  rc.sim.world().set_resource<Viewer>(Viewer{rc.camera});
  // --start-at: simulate without rendering.
  uint64_t ff = rc.clock.steps_for_fast_forward(o.start_at);
  rc.sim.step(ff);
  rc.clock.on_steps_run(ff);

  if (!headless) {
    try {
      return detail::run_windowed(rc);
    } catch (const WindowUnavailable& e) {
      std::printf("cumulo: %s: running headless\n", e.what());
      if (rc.opt.frames == 0) rc.opt.frames = kDefaultHeadlessFrames;
    }
  }
  return run_headless(rc);
}

void register_app_commands(CommandRegistry& registry, const Modules& modules) {
  registry.add({"run", "run a level: in a window, or headless (PNG screenshot, JSON stats)", [modules](int argc, char** argv) {
                  auto o = parse_run_options(argc, argv, modules);
                  if (!o) return 0;
                  return run_level(*o, modules);
                }});
}

}  // namespace cumulo::app
