#include "engine/app/run_options.h"

#include <array>
#include <cstdlib>
#include <filesystem>

#include "engine/core/args.h"
#include "engine/core/error.h"

namespace cumulo::app {

void parse_size(const std::string& text, uint32_t& width, uint32_t& height) {
  size_t x = text.find_first_of("xX");
  auto bad = [&]() { fail("--size: expected WIDTHxHEIGHT such as 640x360, got \"%s\"", text.c_str()); };
  if (x == std::string::npos || x == 0 || x + 1 >= text.size()) bad();
  char* end = nullptr;
  std::string ws = text.substr(0, x), hs = text.substr(x + 1);
  long w = std::strtol(ws.c_str(), &end, 10);
  if (*end) bad();
  long h = std::strtol(hs.c_str(), &end, 10);
  if (*end) bad();
  if (w < 1 || h < 1 || w > 16384 || h > 16384) fail("--size: %s is outside 1x1..16384x16384", text.c_str());
  width = static_cast<uint32_t>(w);
  height = static_cast<uint32_t>(h);
}

std::optional<RunOptions> parse_run_options(int argc, char** argv, const Modules& modules, const char* command) {
  RunOptions o;
  std::string mode = "30", size;
  static constexpr std::array kAerialNames{EnumName<bool>{true, "lut"}, EnumName<bool>{false, "fog"}};
  float tod = -1.0f;
  bool dynres = false;
  double budget_scale = 1.0;
  float resolution_scale = 1.0f;
  ArgParser p(command,
              "Run a level: a fixed-step simulation (ECS systems in phases) and the renderer (render graph:\n"
              "geometry, sky, tonemap). Opens a window when a display exists, otherwise runs headless.");
  p.positional("LEVEL", "level JSON file, e.g. content/levels/sample/level.json", &o.level)
      .flag("--headless", "no window at all: render offscreen, advance 1/mode s per frame (reproducible)", &o.headless)
      .option("--frames", "N", "frames to render, then exit (headless default 1; windowed: until closed)", &o.frames)
      .option("--size", "WxH", "output size in pixels (default 1280x720)", &size)
      .option("--mode", "30|40|60", "budget mode: target frame rate the renderer plans for (default 30)", &mode)
      .option("--screenshot", "PATH", "write the last frame as PNG and print its path", &o.screenshot)
      .option("--camera", "NAME", "start from this named camera of the level (ground, mixed, immersed, ...)", &o.camera)
      .option("--time-of-day", "HOURS", "sun position as local time 0..24 (overrides the level)", &tod)
      .range(0.0, 24.0)
      .option("--seed", "N", "random seed of the simulation (default 1)", &o.seed)
      .option("--start-at", "SECONDS", "simulate this long before the first rendered frame (no rendering)", &o.start_at)
      .range(0.0, 86400.0 * 30)
      .option("--stats", "PATH", "write JSON statistics: per-pass GPU ms, CPU frame ms, device, validation errors, memory", &o.stats)
      .option("--dump-graph", "FILE", "write the compiled render graph of the first frame (Graphviz if FILE ends in .dot)", &o.dump_graph)
      .option("--sim-hz", "HZ", "fixed simulation rate (default 60)", &o.sim_hz)
      .range(1, 1000)
      .option("--event", "NAME@SECONDS", "fire a gameplay event at a simulation time (repeatable), e.g. stormbird_killed@12",
              [&o](const std::string& v) { o.events.push_back(parse_scheduled_event(v, "--event")); })
      .option("--record", "FILE", "write the run's inputs (camera path, events, seed) as JSON for --replay", &o.record)
      .option("--replay", "FILE",
              "run from a recording: its seed, step rate, camera path and events (headless: as many frames as it "
              "lasts unless --frames)",
              &o.replay)
      .choice("--aerial-perspective", kAerialNames,
              "aerial perspective of terrain and clouds: the atmosphere's froxels (default) or the exponential height fog",
              &o.aerial_lut)
      .option("--lod-error", "PX",
              "large meshes (the terrain) are drawn per chunk at the coarsest level of detail whose error projects "
              "within PX pixels (default 3; 0: full detail everywhere)",
              &o.lod_error_px)
      .range(0, 100)
      .on_off("--dynamic-resolution",
              "scale the cloud march and the 2.5D sky so the frame's GPU time stays inside the budget mode's budget "
              "(default on in a window, off headless: a headless image must not depend on the machine's speed)",
              &dynres)
      .option("--budget-scale", "X",
              "the budget modes' frame budgets times X (default: 3 on a CPU device, where 60 Hz plans for 50 ms; "
              "1 on a GPU)",
              &budget_scale)
      .range(0.01, 1000)
      .option("--resolution-scale", "S",
              "render the cloud march and the 2.5D sky at S times the output's width and height, fixed "
              "(0.25..1; no dynamic resolution)",
              &resolution_scale)
      .range(0.25, 1.0);
  for (const auto& m : modules) m->add_run_options(p);
  if (!p.parse(argc, argv)) return std::nullopt;
  for (const auto& m : modules) m->check_run_options();
  o.mode = render::parse_budget_mode(mode);
  if (!size.empty()) {
    parse_size(size, o.width, o.height);
    o.size_set = true;
  }
  // Ranges (and finiteness: --start-at nan would be ~9e18 fast-forward steps) are checked by the parser.
  if (p.was_set("--time-of-day")) o.time_of_day = tod;
  o.frames_set = p.was_set("--frames");
  o.seed_set = p.was_set("--seed");
  o.sim_hz_set = p.was_set("--sim-hz");
  o.camera_set = p.was_set("--camera");
  if (p.was_set("--dynamic-resolution")) o.dynamic_resolution = dynres;
  if (p.was_set("--budget-scale")) o.budget_scale = budget_scale;
  if (p.was_set("--resolution-scale")) {
    if (o.dynamic_resolution.value_or(false))
      fail("--resolution-scale and --dynamic-resolution on: a fixed scale or a dynamic one, not both");
    o.resolution_scale = resolution_scale;
  }
  if (!o.replay.empty() && !o.events.empty())
    fail("--event and --replay: a replay fires the recording's events (record a new run to change them)");
  if (!o.replay.empty() && !o.record.empty() &&
      std::filesystem::weakly_canonical(o.replay) == std::filesystem::weakly_canonical(o.record))
    fail("--record %s: the same file as --replay", o.record.c_str());
  if (o.headless && o.frames == 0) o.frames = kDefaultHeadlessFrames;
  return o;
}

}  // namespace cumulo::app
