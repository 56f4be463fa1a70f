#include "engine/app/simulation.h"
#include "engine/app/module.h"

#include "engine/app/game_events.h"
#include "engine/app/recording.h"
#include "engine/core/error.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"
#include "engine/scene/level.h"
#include "engine/scene/serialization.h"
#include "engine/scene/sun.h"

namespace cumulo::app {

void register_engine_systems(ecs::Scheduler& scheduler) {
  // Input phase, in this order: a replay's pose and events, the recorder, then the scheduled events.
  add_record_replay_systems(scheduler);
  add_scripted_events_system(scheduler);
  // The day cycle: the TimeOfDay that counts (scene::find_sun) advances at its hours_per_second.
  // Update phase: gameplay systems in PreUpdate may set the time first.
  scheduler.add_system(ecs::Phase::Update, "time_of_day", [](ecs::World& w, const ecs::FrameContext& f) {
    if (scene::TimeOfDay* tod = scene::find_sun(w).time) scene::advance_time_of_day(*tod, f.dt);
  });
}

Simulation::Simulation(const SimulationDesc& desc) : modules_(desc.modules), sim_hz_(desc.sim_hz) {
  world_.set_resource<SimulationSeed>(SimulationSeed{desc.seed});
  auto& registry = world_.set_resource<ecs::ComponentRegistry>();
  scene::register_components(registry);
  register_engine_systems(scheduler_);
  for (const auto& m : desc.modules) {
    m->register_components(registry);
    m->register_systems(scheduler_);
  }
  level_ = scene::load_level(desc.level, world_, registry);
  if (desc.time_of_day) scene::time_of_day_to_set(world_).hours = *desc.time_of_day;
  for (const auto& m : desc.modules) m->on_level_loaded(world_, level_);
}

void Simulation::step(uint64_t steps) {
  for (uint64_t i = 0; i < steps; ++i) scheduler_.step(world_, step_seconds());
}

void Simulation::extract() { scheduler_.extract(world_); }

ecs::Entity Simulation::camera(const std::string& name) const {
  const std::string file = level_.file.string();
  if (name.empty()) {
    // The level's first camera, named or not (by name, an unnamed one could not be found).
    const ecs::Entity first = scene::first_camera(world_);
    if (first.is_null()) fail("%s: the level has no camera (an entity with Camera and Transform)", file.c_str());
    return first;
  }
  try {
    return scene::find_camera(world_, name);
  } catch (const Error& e) {
    fail("%s: %s", file.c_str(), e.what());  // a message about the level names its file
  }
}

}  // namespace cumulo::app
