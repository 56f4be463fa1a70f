#pragma once
// Named gameplay events (issue 9's triggers): game code fires them, systems react (the clouds module's
// triggers and Stormbird dissipation). They are ECS typed events (engine/ecs/events.h), so a system that
// runs once per step sees each exactly once.
//
//   fire_event(world, "stormbird_killed");                         // from game code, any phase
//   [reader = ecs::EventReader<GameEvent>{}](ecs::World& w, ...) mutable {
//     for (const GameEvent& e : w.read(reader)) if (e.name == "stormbird_killed") ...;
//   }
//
// `cumulo run ... --event NAME@SECONDS` (repeatable) schedules events at simulation times: the
// ScheduledEvents resource, fired by the engine's "scripted events" system (Input phase) at the step that
// reaches the time. Input from outside the simulation (a key, an editor button) goes through
// schedule_event(), so `--record` writes it and `--replay` fires it at the same step; fire_event() from
// inside a system is simulation state and replays by itself.
#include <string>
#include <vector>

#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"

namespace cumulo::app {

struct GameEvent {
  std::string name;
};
void fire_event(ecs::World& world, std::string name);

struct ScheduledEvent {
  std::string name;
  double seconds = 0.0;  // simulation time
  bool fired = false;
  uint64_t step = 0;  // the step it fired at (when fired)
};
// "NAME@SECONDS": a name of letters, digits, '_', '-', '.'; seconds finite and >= 0. Throws cumulo::Error
// naming `flag` and the text.
ScheduledEvent parse_scheduled_event(const std::string& text, const std::string& flag);

struct ScheduledEvents {
  std::vector<ScheduledEvent> events;
};
// Schedules `name` at `seconds` of simulation time (now or later: the next step fires it).
void schedule_event(ecs::World& world, std::string name, double seconds);
// Input phase: fires every scheduled event whose time falls before the end of this step.
void add_scripted_events_system(ecs::Scheduler& s);

}  // namespace cumulo::app
