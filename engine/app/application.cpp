#include "engine/app/application.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "engine/app/detail/run_context.h"
#include "engine/app/frame_output.h"
#include "engine/app/headless_session.h"
#include "engine/app/recording.h"
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
  HeadlessSession session(rc.sim, rc.modules, o.width, o.height, o.aerial_lut);
  session.renderer().set_lod_error_px(o.lod_error_px);
  detail::configure_resolution(rc, session.ctx(), false);
  const uint32_t frames = std::max(1u, o.frames);
  for (uint32_t f = 1; f <= frames; ++f) {
    Stopwatch cpu, wall;
    const uint32_t steps = rc.clock.steps_for_fixed_frame(f, uint32_t(render::budget_hz(o.mode)));
    rc.sim.step(steps);
    rc.clock.on_steps_run(steps);
    render::FrameSnapshot snap = session.extract(rc.camera, o.mode);
    snap.resolution_scale = detail::next_resolution_scale(rc);
    session.submit(snap);
    rc.stats.add_cpu_frame_ms(cpu.ms());
    session.wait_frame();
    const auto timings = session.pass_timings();
    rc.stats.add_gpu_frame(timings);
    // Headless waits for each frame: its timings are complete (the wall clock, with no pacing, where the
    // device has no timestamps).
    detail::feed_resolution(rc, timings, wall.ms());
    rc.stats.add_resolution_scale(snap.resolution_scale);
    if (f == 1 && !o.dump_graph.empty()) detail::write_graph_dump(o.dump_graph, session.renderer().last_compiled());
  }
  rc.stats.set_frames(frames);
  if (!o.screenshot.empty()) {
    gpu::write_png(o.screenshot, session.screenshot());
    std::printf("cumulo: wrote screenshot %s\n", o.screenshot.c_str());
  }
  detail::write_stats(rc, session.ctx(), o.width, o.height);
  return session.finish();
}

}  // namespace

namespace {

// --replay: the recording's seed, step rate, time of day and camera replace the flags (said when they differ).
void apply_recording_settings(RunOptions& o, const Recording& r) {
  auto note = [&](const char* what, const std::string& given, const std::string& recorded) {
    if (given != recorded) std::printf("cumulo: --replay %s: %s %s (recorded), not %s\n", o.replay.c_str(), what, recorded.c_str(), given.c_str());
  };
  if (o.seed_set) note("seed", std::to_string(o.seed), std::to_string(r.seed));
  if (o.sim_hz_set) note("sim-hz", std::to_string(o.sim_hz), std::to_string(r.sim_hz));
  if (o.camera_set) note("camera", o.camera, r.camera);
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!r.level.empty() && !fs::equivalent(fs::path(r.level), fs::path(o.level), ec))
    std::printf("cumulo: --replay %s: recorded on %s, replayed on %s\n", o.replay.c_str(), r.level.c_str(), o.level.c_str());
  o.seed = r.seed;
  o.sim_hz = r.sim_hz;
  o.time_of_day = r.time_of_day;
  o.camera = r.camera;
}

}  // namespace

int run_level(const RunOptions& options, const Modules& modules) {
  RunOptions o = options;
  std::optional<Recording> replay;
  if (!o.replay.empty()) {
    replay = load_recording(o.replay);
    apply_recording_settings(o, *replay);
  }
  bool headless = o.headless;
  if (o.require_window && (headless || !platform::display_available()))
    fail("%s", headless ? "this command needs a window: --headless is not allowed"
                        : "this command needs a display (DISPLAY or WAYLAND_DISPLAY); without one, run it under "
                          "xvfb-run -a");
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
  ecs::World& world = rc.sim.world();
  world.set_resource<Viewer>(Viewer{rc.camera});
  world.set_resource<ScheduledEvents>(ScheduledEvents{o.events});
  if (!o.record.empty()) start_recording(rc.sim, Recording{o.level, o.seed, o.sim_hz, o.time_of_day, o.camera});
  if (replay) {
    start_replay(rc.sim, *replay);
    // Headless without --frames: as many frames as the recording lasts (after --start-at).
    const uint64_t start = rc.clock.steps_for_fast_forward(o.start_at);
    if (headless && !o.frames_set && replay->steps > start) {
      const double steps_per_frame = double(o.sim_hz) / double(render::budget_hz(o.mode));
      rc.opt.frames = uint32_t(std::min<double>(1e6, std::ceil(double(replay->steps - start) / steps_per_frame)));
    }
  }
  // --start-at: simulate without rendering.
  uint64_t ff = rc.clock.steps_for_fast_forward(o.start_at);
  rc.sim.step(ff);
  rc.clock.on_steps_run(ff);

  int code = -1;
  if (!headless) {
    try {
      code = detail::run_windowed(rc);
    } catch (const WindowUnavailable& e) {
      if (o.require_window) fail("cannot open a window: %s", e.what());
      std::printf("cumulo: %s: running headless\n", e.what());
      if (rc.opt.frames == 0) rc.opt.frames = kDefaultHeadlessFrames;
    }
  }
  if (code < 0) code = run_headless(rc);
  if (!o.record.empty()) {
    const Recording r = finish_recording(rc.sim);
    save_recording(o.record, r);
    std::printf("cumulo: recorded %llu steps, %zu camera poses, %zu events to %s\n", (unsigned long long)r.steps,
                r.camera_path.size(), r.events.size(), o.record.c_str());
  }
  return code;
}

void register_app_commands(CommandRegistry& registry, const Modules& modules) {
  registry.add({"run", "run a level: in a window, or headless (PNG screenshot, JSON stats)", [modules](int argc, char** argv) {
                  auto o = parse_run_options(argc, argv, modules);
                  if (!o) return 0;
                  return run_level(*o, modules);
                }});
}

}  // namespace cumulo::app
