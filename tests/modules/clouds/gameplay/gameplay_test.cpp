// Gameplay events and the Stormbird dissipation (issue 9), on the ECS alone (no GPU): scheduled events
// fire at their step, the dissipation rises monotonically to 1 over its duration after its event and
// resets, and bad `--event` texts and components are refused naming the place.
#include <gtest/gtest.h>

#include <string>

#include "engine/core/error.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"
#include "modules/clouds/gameplay/game_events.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/scene/cloudscape.h"

using namespace cumulo;
using namespace cumulo::clouds;
using namespace cumulo::clouds::gameplay;

namespace {

struct Sim {
  ecs::World world;
  ecs::Scheduler sched;
  ecs::Entity storm;
  int heard = 0;
  Sim() {
    add_scripted_events_system(sched);
    add_stormbird_system(sched);
    sched.add_system(ecs::Phase::PostUpdate, "listener",
                     [this, reader = ecs::EventReader<GameEvent>{}](ecs::World& w, const ecs::FrameContext&) mutable {
                       for (const GameEvent& e : w.read(reader)) heard += e.name == "stormbird_killed";
                     });
    storm = world.create();
    Cloudscape c;
    c.dissipation = 0.1f;  // the level's own value: the floor
    world.emplace<Cloudscape>(storm, c);
    StormbirdDissipation d;
    d.duration_s = 2.0f;
    world.emplace<StormbirdDissipation>(storm, d);
  }
  float dissipation() const { return world.get<Cloudscape>(storm).dissipation; }
  void steps(int n) {
    for (int i = 0; i < n; ++i) sched.step(world, 0.1);
  }
};

TEST(Gameplay, ScheduledEventDissipatesTheStormMonotonicallyAndResets) {
  Sim s;
  s.world.set_resource<ScheduledEvents>(ScheduledEvents{{parse_scheduled_event("stormbird_killed@1", "--event"),
                                                         parse_scheduled_event("stormbird_reset@5", "--event")}});
  s.steps(10);  // t = 0 .. 1 s: not yet
  EXPECT_FLOAT_EQ(s.dissipation(), 0.1f);
  EXPECT_EQ(s.heard, 0);
  float last = s.dissipation();
  for (int i = 0; i < 25; ++i) {  // 1 .. 3.5 s: rises over the 2 s duration, never falls
    s.steps(1);
    EXPECT_GE(s.dissipation(), last);
    last = s.dissipation();
  }
  EXPECT_EQ(s.heard, 1);  // fired once
  EXPECT_FLOAT_EQ(s.dissipation(), 1.0f);
  s.steps(20);  // the reset at 5 s
  EXPECT_FLOAT_EQ(s.dissipation(), 0.1f);
  // Fired from game code.
  fire_event(s.world, "stormbird_killed");
  s.steps(10);
  EXPECT_NEAR(s.dissipation(), 0.5f, 0.051f);  // 1 s of 2
}

TEST(Gameplay, BadEventTextsAndComponentsNameThePlace) {
  for (const char* bad : {"stormbird_killed", "@3", "x@", "x@-1", "x@nan", "x@1e99", "bad name@1", "x@1s"}) {
    try {
      parse_scheduled_event(bad, "--event");
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--event"), std::string::npos) << e.what();
    }
  }
  const ScheduledEvent ok = parse_scheduled_event("stormbird_killed@12.5", "--event");
  EXPECT_EQ(ok.name, "stormbird_killed");
  EXPECT_DOUBLE_EQ(ok.seconds, 12.5);
  const JsonDocument doc = parse_json_text(R"({"event": "x", "duration": 3})", "level.json");
  try {
    stormbird_dissipation_from_json(doc.view());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key \"duration\""), std::string::npos) << e.what();
  }
  const JsonDocument zero = parse_json_text(R"({"duration_s": 0})", "level.json");
  EXPECT_THROW(stormbird_dissipation_from_json(zero.view()), Error);
}

}  // namespace
