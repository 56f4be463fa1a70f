#pragma once
// `cumulo run` command line (issue 2). Parsed with engine/core/args.h; every flag is in --help.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/app/game_events.h"
#include "engine/app/module.h"
#include "engine/render/budget_mode.h"
#include "engine/render/mesh_lod.h"

namespace cumulo::app {

struct RunOptions {
  std::string level;                 // path to level.json
  bool headless = false;
  uint32_t frames = 0;               // 0: until the window closes (windowed); headless default below
  uint32_t width = 1280, height = 720;
  bool size_set = false;
  render::BudgetMode mode = render::BudgetMode::Hz30;
  std::string screenshot;            // PNG of the last frame (headless or windowed)
  std::string camera;                // named camera of the level; empty: the level's default
  std::optional<float> time_of_day;  // hours 0..24; overrides the level's TimeOfDay
  uint64_t seed = 1;
  double start_at = 0.0;             // seconds of simulation run before the first rendered frame
  std::string stats;                 // JSON statistics path
  std::string dump_graph;            // compiled render graph (text, or Graphviz when it ends in .dot)
  uint32_t sim_hz = 60;              // fixed simulation rate
  bool frames_set = false, seed_set = false, sim_hz_set = false, camera_set = false;
  std::vector<ScheduledEvent> events;  // --event NAME@SECONDS (repeatable)
  std::string record;                // --record FILE: write the run's inputs (engine/app/recording.h)
  std::string replay;                // --replay FILE: drive the run from a recording
  bool aerial_lut = true;            // --aerial-perspective lut|fog: the atmosphere's froxels or the height fog
  float lod_error_px = render::kDefaultLodErrorPx;        // --lod-error PX: large meshes' level of detail (render/mesh_lod.h)
  bool require_window = false;       // `cumulo edit`: no headless fallback (fail when no window opens)
  // Budget modes that hold a budget (render/dynamic_resolution.h).
  std::optional<bool> dynamic_resolution;  // --dynamic-resolution on|off; unset: on in a window, off headless
  std::optional<double> budget_scale;      // --budget-scale X; unset: the device's default (CPU 3, GPU 1)
  std::optional<float> resolution_scale;   // --resolution-scale S: a fixed scale (no dynamic resolution)
};

// Frames a headless run renders when --frames is not given.
constexpr uint32_t kDefaultHeadlessFrames = 1;

// Parses argv (argv[0] = "run"), with the flags every module adds (Module::add_run_options, checked by
// Module::check_run_options). Returns nullopt after printing --help. Throws cumulo::Error on bad
// values: "--size: expected WIDTHxHEIGHT ...", "--mode: ...", out-of-range time of day, etc.
// `command` names the command in --help and errors (`cumulo edit` parses the same flags).
std::optional<RunOptions> parse_run_options(int argc, char** argv, const Modules& modules = {},
                                            const char* command = "cumulo run");

// "640x360" -> (640, 360); throws cumulo::Error for anything else or sizes outside 1..16384.
void parse_size(const std::string& text, uint32_t& width, uint32_t& height);

}  // namespace cumulo::app
