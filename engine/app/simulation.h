#pragma once
// The simulated side of `cumulo run`: the level's ECS world and the fixed-step scheduler with the
// engine's systems in phases. Deterministic: the state after N steps depends only on the level, the
// seed and N (no wall clock, no Vulkan).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"
#include "engine/app/module_hooks.h"
#include "engine/app/sim_resources.h"
#include "engine/ecs/world.h"
#include "engine/scene/level.h"

namespace cumulo::app {

struct SimulationDesc {
  std::filesystem::path level;
  uint64_t seed = 1;
  uint32_t sim_hz = 60;
  std::optional<float> time_of_day;  // hours; overrides the TimeOfDay that counts (scene::find_sun)
  // Register their components and systems before the level loads; told when it has loaded.
  Modules modules;
};

class Simulation {
 public:
  // Loads the level (throws cumulo::Error naming the file and place) and registers the engine systems.
  explicit Simulation(const SimulationDesc& desc);

  ecs::World& world() { return world_; }
  const ecs::World& world() const { return world_; }
  ecs::Scheduler& scheduler() { return scheduler_; }

  void step(uint64_t steps);  // fixed steps of 1/sim_hz s
  void extract();             // the Extract phase (systems that prepare render data)
  double step_seconds() const { return 1.0 / sim_hz_; }
  double sim_seconds() const { return double(steps()) / sim_hz_; }  // steps / rate: exact
  uint64_t steps() const { return scheduler_.steps(); }
  double time() const { return scheduler_.time(); }

  // The camera entity to render from: `name`, or the level's first camera when empty.
  ecs::Entity camera(const std::string& name) const;
  const scene::LevelInfo& level() const { return level_; }

 private:
  // Kept alive with the simulation: their systems capture them.
  Modules modules_;
  scene::LevelInfo level_;
  ecs::World world_;
  ecs::Scheduler scheduler_;
  uint32_t sim_hz_ = 60;
};

// The engine's own systems (replay and recording, the scheduled events, the day cycle). Modules add
// theirs through Module::register_systems.
void register_engine_systems(ecs::Scheduler& scheduler);

}  // namespace cumulo::app
