#pragma once
// Named gameplay events (issue 9's triggers): game code fires them, systems react. They are ECS typed
// events (engine/ecs/events.h), so a system that runs once per step sees each exactly once.
//
//   fire_event(world, "stormbird_killed");                         // from game code, any phase
//   [reader = ecs::EventReader<GameEvent>{}](ecs::World& w, ...) mutable {
//     for (const GameEvent& e : w.read(reader)) if (e.name == "stormbird_killed") ...;
//   }
//
// `cumulo run ... --event NAME@SECONDS` (repeatable) schedules events at simulation times: the
// ScheduledEvents resource, fired by the "scripted events" system at the step that reaches the time.
#include <string>
#include <vector>

#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"

namespace cumulo::clouds::gameplay {

struct GameEvent {
  std::string name;
};
void fire_event(ecs::World& world, std::string name);

struct ScheduledEvent {
  std::string name;
  double seconds = 0.0;  // simulation time
  bool fired = false;
};
// "NAME@SECONDS": a name of letters, digits, '_', '-', '.'; seconds finite and >= 0. Throws cumulo::Error
// naming `flag` and the text.
ScheduledEvent parse_scheduled_event(const std::string& text, const std::string& flag);

struct ScheduledEvents {
  std::vector<ScheduledEvent> events;
};
// Input phase: fires every scheduled event whose time falls before the end of this step.
void add_scripted_events_system(ecs::Scheduler& s);

}  // namespace cumulo::clouds::gameplay
