#pragma once
// `cumulo run --record FILE` / `--replay FILE` (issue 9): a run's inputs, so that the same inputs and seed
// give the same simulation, step for step: the level, seed, step rate, time-of-day override and camera,
// the viewer's camera path (its pose at each step where it changed) and the named input events
// (engine/app/game_events.h) with the step each fired at. Everything else (weather, triggers, lightning,
// dissipation) is simulation state and follows from these.
//
//   {"format": "cumulo-recording", "version": 1, "level": "content/levels/sample/level.json",
//    "seed": 1, "sim_hz": 60, "time_of_day": 16.5, "camera": "ground", "steps": 1800,
//    "camera_path": [{"step": 0, "position": [x, y, z], "rotation": [w, x, y, z]}, ...],
//    "events": [{"step": 61, "name": "stormbird_killed"}]}
//
// ("time_of_day" only when the run overrode the level's; "camera" "" is the level's first camera.)
// Replaying, an Input-phase system puts the recorded pose on the viewer before each step runs and fires
// each recorded event at its step; --event is then not taken (the recording's events are the inputs).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/core/json.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"

namespace cumulo::app {

class Simulation;

struct CameraSample {
  uint64_t step = 0;  // the pose holds from this step on
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

struct RecordedEvent {
  uint64_t step = 0;  // fired at the start of this step
  std::string name;
};

struct Recording {
  std::string level;
  uint64_t seed = 1;
  uint32_t sim_hz = 60;
  std::optional<float> time_of_day;
  std::string camera;
  uint64_t steps = 0;  // how long the recorded run simulated
  std::vector<CameraSample> camera_path;  // steps ascending
  std::vector<RecordedEvent> events;      // steps ascending
};

Json recording_to_json(const Recording& r);
// Throws cumulo::Error naming the file and the JSON path ("run.json: $.events[2].step: expected ...").
Recording recording_from_json(const JsonView& v);
Recording load_recording(const std::filesystem::path& path);
// Atomic (a temporary file renamed over the old one); throws naming the path on failure.
void save_recording(const std::filesystem::path& path, const Recording& r);

// Starts recording `sim`'s inputs (from its next step): the viewer's pose (app::Viewer) and the scheduled
// events as they fire. `header` gives level, seed, step rate, time of day and camera.
void start_recording(Simulation& sim, const Recording& header);
// The inputs recorded so far, with `steps` set to the steps simulated.
Recording finish_recording(const Simulation& sim);
// Drives `sim` from `r`: the viewer follows the camera path, the events fire at their steps; throws
// when the simulation's step rate differs from the recording's.
void start_replay(Simulation& sim, const Recording& r);
// True while a replay is attached (the windowed loop then leaves the camera to it).
bool replaying(const ecs::World& world);

// The engine's Input-phase systems behind the two (no-ops without a recording or replay attached).
void add_record_replay_systems(ecs::Scheduler& s);

}  // namespace cumulo::app
