#include "engine/app/game_events.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "engine/core/error.h"

namespace cumulo::app {

void fire_event(ecs::World& world, std::string name) { world.emit(GameEvent{std::move(name)}); }

ScheduledEvent parse_scheduled_event(const std::string& text, const std::string& flag) {
  const size_t at = text.rfind('@');
  if (at == std::string::npos || at == 0 || at + 1 == text.size())
    fail("%s: expected NAME@SECONDS (e.g. stormbird_killed@12.5), got \"%s\"", flag.c_str(), text.c_str());
  ScheduledEvent e;
  e.name = text.substr(0, at);
  for (char c : e.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      fail("%s: event name \"%s\" may hold letters, digits, '_', '-' and '.' only", flag.c_str(), e.name.c_str());
  const std::string t = text.substr(at + 1);
  char* end = nullptr;
  e.seconds = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || !std::isfinite(e.seconds) || e.seconds < 0.0 || e.seconds > 1e7)
    fail("%s: \"%s\": the time must be a number of seconds in 0..1e7, got \"%s\"", flag.c_str(), text.c_str(), t.c_str());
  return e;
}

void schedule_event(ecs::World& world, std::string name, double seconds) {
  auto* list = world.try_resource<ScheduledEvents>();
  if (!list) list = &world.set_resource<ScheduledEvents>();
  list->events.push_back({std::move(name), seconds});
}

void add_scripted_events_system(ecs::Scheduler& s) {
  s.add_system(ecs::Phase::Input, "scripted events", [](ecs::World& w, const ecs::FrameContext& f) {
    auto* list = w.try_resource<ScheduledEvents>();
    if (!list) return;
    for (ScheduledEvent& e : list->events)
      if (!e.fired && e.seconds < f.time + f.dt) {
        e.fired = true;
        e.step = f.step;
        fire_event(w, e.name);
      }
  });
}

}  // namespace cumulo::app
