#include "modules/clouds/gameplay/stormbird.h"

#include <algorithm>

#include "modules/clouds/gameplay/game_events.h"
#include "modules/clouds/scene/cloudscape.h"

namespace cumulo::clouds::gameplay {

StormbirdDissipation stormbird_dissipation_from_json(const JsonView& v) {
  for (const std::string& k : v.keys())
    if (k != "event" && k != "reset_event" && k != "duration_s")
      v.fail("unknown key \"" + k + "\" (expected event, reset_event, duration_s)");
  StormbirdDissipation s;
  s.event = v.get<std::string>("event", s.event);
  s.reset_event = v.get<std::string>("reset_event", s.reset_event);
  if (s.event.empty()) v["event"].fail("expected an event name");
  if (v.has("duration_s")) s.duration_s = v["duration_s"].as_float_in(0.01f, 3600.0f);
  return s;
}

Json stormbird_dissipation_to_json(const StormbirdDissipation& s) {
  return {{"event", s.event}, {"reset_event", s.reset_event}, {"duration_s", s.duration_s}};
}

void register_stormbird_component(ecs::ComponentRegistry& registry) {
  registry.register_component<StormbirdDissipation>("StormbirdDissipation", stormbird_dissipation_to_json,
                                                    stormbird_dissipation_from_json);
}

void add_stormbird_system(ecs::Scheduler& s) {
  s.add_system(ecs::Phase::Update, "stormbird dissipation",
               [reader = ecs::EventReader<GameEvent>{}](ecs::World& w, const ecs::FrameContext& f) mutable {
                 std::vector<std::string> fired;
                 for (const GameEvent& e : w.read(reader)) fired.push_back(e.name);
                 w.view<StormbirdDissipation, Cloudscape>().each([&](StormbirdDissipation& d, Cloudscape& c) {
                   if (d.base < 0.0f) d.base = c.dissipation;
                   for (const std::string& name : fired) {
                     if (name == d.event) d.active = true;
                     if (name == d.reset_event) d.active = false, d.progress = 0.0f;
                   }
                   if (d.active) d.progress = std::min(1.0f, d.progress + float(f.dt) / d.duration_s);
                   c.dissipation = std::max(d.base, d.progress);
                 });
               });
}

}  // namespace cumulo::clouds::gameplay
