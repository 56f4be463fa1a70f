#pragma once
// CloudGrowth (issue 26): a Cloudscape entity whose cloud grows while the game runs: the cloud-formation simulation
// (a grow spec, modules/clouds/bake/grow/grow_spec.h) stepped on the GPU at a rate of its own, from a start event
// or a weather state, until its last step, where it holds (or a reset event brings it back to its first step).
// This component owns when and how far the simulation runs; the renderer (grow_gpu) owns the steps themselves and
// catches up with `target_steps` at most a few steps a frame.
//
//   "CloudGrowth": {"spec": "grown/storm_growth.json",       a grow spec, relative to the level file
//                   "event": "storm_builds",                   starts it (empty: only the states below, or at load)
//                   "states": ["storm", "stormbird"],          a weather scheduler entering one of these starts it
//                   "reset_event": "storm_clears",             back to the first step, stopped
//                   "speed": 12,                               physical seconds simulated per second of play
//                   "voxel": 8,                                the march's voxel (game m): the simulation's cells
//                                                              are cut into ceil(cell / voxel) voxels a side
//                   "start_running": false}                    true: runs from the level's start
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/json.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"

namespace cumulo::clouds::gameplay {

struct CloudGrowth {
  std::string spec;                 // as written in the level (resolved against the level's folder by the renderer)
  std::string event;                // empty: none
  std::vector<std::string> states;  // weather states that start it
  std::string reset_event;          // empty: none
  float speed = 12.0f;              // physical s per s of play
  float voxel = 8.0f;               // the grown images' voxel (game m; 8: the offline bake's)
  bool start_running = false;
  std::string where;                // "level.json: $.entities[3].components.CloudGrowth", for messages
  std::filesystem::path resolved_spec;  // set by resolve_cloud_growth

  // Runtime (the system's; the editor may set `paused` and request `step_once`).
  bool running = false;
  bool paused = false;
  bool step_once = false;    // while paused: one more step, then paused again
  bool ended = false;        // the spec's last step reached: holds it
  double sim_seconds = 0.0;  // physical seconds simulated since the (re)start
  int target_steps = 0;      // steps the simulation should have taken by now (<= last_step)
  int last_step = 0;         // the spec's step count (set by whoever resolved the spec; 0: not known yet)
  float step_seconds = 0.0f; // the spec's dt (physical seconds per step; 0: not known yet)
  uint32_t generation = 0;   // +1 at every reset: the renderer restarts the simulation from its first step
};

CloudGrowth cloud_growth_from_json(const JsonView& v);
Json cloud_growth_to_json(const CloudGrowth& g);
void register_cloud_growth_component(ecs::ComponentRegistry& registry);
// Loads the spec (relative to the level's folder): its step count and dt. Throws naming the component's place and
// the spec's file for a missing or bad spec.
void resolve_cloud_growth(CloudGrowth& g, const std::filesystem::path& level_dir);
// Update phase, after the weather: reacts to the events and the weather states, advances target_steps.
void add_cloud_growth_system(ecs::Scheduler& s);
// Back to the first step, stopped: the renderer sees a new generation and starts the simulation again.
void restart_cloud_growth(CloudGrowth& g);
// What the editor's controls (its events panel and its scripts) do: a reset fires the growth's reset event at
// `sim_time` when it has one (so the rest of the level hears it), else restarts it now; a single step is asked of a
// growth that runs paused (step_once). Its state as the editor names it: "ended", "not started", "paused", "growing".
void request_cloud_growth_reset(ecs::World& world, CloudGrowth& g, double sim_time);
bool cloud_growth_can_step_once(const CloudGrowth& g);
const char* cloud_growth_state(const CloudGrowth& g);
// Steps per second of play (speed / dt); 0 until the spec is known.
double growth_steps_per_second(const CloudGrowth& g);

}  // namespace cumulo::clouds::gameplay
