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

#include "engine/app/simulation.h"
#include "modules/clouds/gameplay/lightning.h"

namespace {

TEST(Lightning, AFlashRisesFlickersAndEndsAndFeedsTheLightList) {
  ecs::World w;
  ecs::Scheduler sched;
  add_lightning_system(sched);
  strike_lightning(w, {0, 900, 0}, LightningKind::Internal, 60.0f);
  float peak = 0.0f;
  int direction_changes = 0;
  float last = 0.0f, last_delta = 0.0f;
  for (int i = 0; i < 60; ++i) {  // 1 s at 60 Hz: the 0.8 s flash and after
    const auto lights = lightning_lights(w, 4);
    const float k = lights.empty() ? 0.0f : lights[0].intensity;
    peak = std::max(peak, k);
    const float delta = k - last;
    if (i > 2 && delta * last_delta < 0.0f) ++direction_changes;
    last_delta = delta, last = k;
    sched.step(w, 1.0 / 60.0);
  }
  EXPECT_GT(peak, 30.0f);
  EXPECT_LE(peak, 60.0f);
  EXPECT_GE(direction_changes, 3);  // it flickers
  EXPECT_TRUE(lightning_lights(w, 4).empty());
  EXPECT_EQ(w.alive_count(), 0u);  // the flash's entity is gone
}

TEST(Lightning, TheWeatherSpawnsAtItsRateInsideItsVolumeDeterministically) {
  auto spawn = [](uint64_t seed, std::vector<glm::vec3>* positions) {
    ecs::World w;
    w.set_resource<app::SimulationSeed>(app::SimulationSeed{seed});
    LightningWeather lw;
    lw.per_minute = 60.0f;
    lw.box_min = {-100, 600, -100};
    lw.box_max = {100, 900, 100};
    w.set_resource<LightningWeather>(lw);
    ecs::Scheduler sched;
    int strikes = 0;
    sched.add_system(ecs::Phase::PostUpdate, "count", [&](ecs::World& world, const ecs::FrameContext&) {
      world.view<const LightningEvent>().each([&](const LightningEvent& l) {
        if (l.age_s == 0.0f) {
          ++strikes;
          positions->push_back(l.position);
          EXPECT_TRUE(glm::all(glm::greaterThanEqual(l.position, glm::vec3(-100, 600, -100))));
          EXPECT_TRUE(glm::all(glm::lessThanEqual(l.position, glm::vec3(100, 900, 100))));
        }
      });
    });
    add_lightning_system(sched);  // after the counter: a new flash is seen at age 0 in the next step
    for (int i = 0; i < 120 * 60; ++i) sched.step(w, 1.0 / 60.0);
    return strikes;
  };
  std::vector<glm::vec3> a, b, c;
  const int na = spawn(5, &a), nb = spawn(5, &b), nc = spawn(6, &c);
  std::printf("  120 s at 60 per minute: %d strikes (Poisson: 120 +- 11)\n", na);
  EXPECT_GT(na, 80);
  EXPECT_LT(na, 160);
  EXPECT_EQ(na, nb);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

}  // namespace

#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace {

Trigger trigger_from(const std::string& text) {
  const JsonDocument doc = parse_json_text(text, "level.json");
  return trigger_from_json(doc.view());
}

struct TriggerSim {
  ecs::World w;
  ecs::Scheduler sched;
  ecs::Entity viewer, cloud, weather;
  TriggerSim() {
    add_scripted_events_system(sched);
    add_trigger_system(sched);
    add_lightning_system(sched);
    viewer = named("viewer");
    w.emplace<scene::Transform>(viewer).position = {0, 0, 0};
    w.set_resource<app::Viewer>(app::Viewer{viewer});
    cloud = named("cloudscape");
    w.emplace<Cloudscape>(cloud);
    w.emplace<scene::Transform>(cloud);
    weather = named("weather");
    weather::WeatherScheduler s;
    s.start = "fair_cumulus";
    s.schedule = {{"fair_cumulus", 1.0f}};
    s.encounter = {{"stormbird", 1.0f}};
    w.emplace<weather::WeatherScheduler>(weather, s);
  }
  ecs::Entity named(const char* name) {
    const ecs::Entity e = w.create();
    w.emplace<ecs::Name>(e, ecs::Name{name});
    return e;
  }
  void move_viewer(glm::vec3 p) { w.get<scene::Transform>(viewer).position = p; }
  void step() {
    sched.step(w, 0.1);
    w.view<weather::WeatherScheduler>().each([](weather::WeatherScheduler& s) { weather::advance(s, 0.1f, 12.0f, 1); });
  }
  weather::WeatherScheduler& sched_state() { return w.get<weather::WeatherScheduler>(weather); }
};

TEST(Triggers, EnterExitEventAndTimeRunTheirActions) {
  TriggerSim s;
  const ecs::Entity storm = s.w.create();
  s.w.emplace<Trigger>(storm, trigger_from(R"({"when": {"enter": {"sphere": {"center": [0, 900, 0], "radius": 500}}},
      "actions": [{"do": "set_weather", "state": "storm"}, {"do": "encounter", "active": true},
                  {"do": "strike_lightning", "position": [0, 900, 0]}]})"));
  s.w.emplace<Trigger>(s.w.create(), trigger_from(R"({"when": {"exit": {"sphere": {"center": [0, 900, 0], "radius": 500}}},
      "actions": [{"do": "encounter", "active": false}]})"));
  s.w.emplace<Trigger>(s.w.create(), trigger_from(R"({"when": {"event": "move_it"}, "once": false,
      "actions": [{"do": "move_cloudscape", "entity": "cloudscape", "position": [100, 0, 0], "euler_deg": [0, 90, 0]}]})"));
  s.w.emplace<Trigger>(s.w.create(), trigger_from(R"({"when": {"time": 2}, "actions": [{"do": "set_time_of_day", "hours": 18.5}]})"));
  s.step();
  s.step();
  EXPECT_FALSE(s.sched_state().encounter_active);
  s.move_viewer({0, 900, 100});  // enters the storm sphere
  s.step();
  EXPECT_TRUE(s.sched_state().encounter_active);
  size_t flashes = 0;
  s.w.view<const LightningEvent>().each([&](const LightningEvent&) { ++flashes; });
  EXPECT_EQ(flashes, 1u);
  s.move_viewer({0, 0, 0});  // leaves
  s.step();
  EXPECT_FALSE(s.sched_state().encounter_active);
  s.move_viewer({0, 900, 0});  // enters again: the enter trigger fired once only
  s.step();
  EXPECT_FALSE(s.sched_state().encounter_active);
  fire_event(s.w, "move_it");
  s.step();
  EXPECT_EQ(s.w.get<scene::Transform>(s.cloud).position, glm::vec3(100, 0, 0));
  for (int i = 0; i < 20; ++i) s.step();  // past t = 2 s
  EXPECT_FLOAT_EQ(scene::time_of_day_to_set(s.w).hours, 18.5f);
}

TEST(Triggers, StartingInsideIsNotEntering) {
  TriggerSim s;
  s.move_viewer({0, 900, 0});
  s.w.emplace<Trigger>(s.w.create(), trigger_from(R"({"when": {"enter": {"box": {"min": [-10, 800, -10], "max": [10, 1000, 10]}}},
      "actions": [{"do": "encounter", "active": true}]})"));
  for (int i = 0; i < 5; ++i) s.step();
  EXPECT_FALSE(s.sched_state().encounter_active);
}

TEST(Triggers, BadTriggersNameThePlace) {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      trigger_from(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  auto has = [](const std::string& m, const std::string& w) { return m.find(w) != std::string::npos; };
  std::string m = error_of(R"({"when": {"event": "x", "time": 3}, "actions": [{"do": "fire_event", "name": "y"}]})");
  EXPECT_TRUE(has(m, "$.when") && has(m, "exactly one")) << m;
  m = error_of(R"({"when": {"event": "x"}, "actions": [{"do": "teleport"}]})");
  EXPECT_TRUE(has(m, "$.actions[0].do") && has(m, "teleport")) << m;
  m = error_of(R"({"when": {"event": "x"}, "actions": [{"do": "set_time_of_day", "hours": 25}]})");
  EXPECT_TRUE(has(m, "$.actions[0].hours")) << m;
  m = error_of(R"({"when": {"event": "x"}, "actions": []})");
  EXPECT_TRUE(has(m, "$.actions") && has(m, "at least one")) << m;
  m = error_of(R"({"when": {"enter": {"sphere": {"center": [0, 0, 0], "radius": 1}}}, "actions": [{"do": "set_weather", "state": "storm", "fast": true}]})");
  EXPECT_TRUE(has(m, "unknown key \"fast\"")) << m;
}

}  // namespace

namespace {

// The bolt of a ground discharge: a connected main channel from the flash down to the ground, branches
// that leave it downward, everything between the ground and the top, the same path for the same seed.
TEST(Lightning, ABoltRunsFromTheFlashToTheGroundWithBranches) {
  using namespace cumulo::clouds::gameplay;
  const glm::vec3 top(100, 760, -50);
  const std::vector<BoltSegment> bolt = lightning_bolt(top, 0.0f, 42);
  ASSERT_GE(bolt.size(), size_t(kBoltMainSegments + 3));  // at least three branch segments
  ASSERT_LE(bolt.size(), size_t(kBoltMaxSegments));
  EXPECT_EQ(bolt.front().a, top);
  for (int i = 1; i < kBoltMainSegments; ++i) EXPECT_EQ(bolt[i].a, bolt[i - 1].b) << "main channel broken at " << i;
  EXPECT_FLOAT_EQ(bolt[kBoltMainSegments - 1].b.y, 0.0f);  // it reaches the ground
  for (const BoltSegment& s : bolt) {
    EXPECT_LE(s.b.y, s.a.y);  // downward
    EXPECT_GE(s.b.y, 0.0f);
    EXPECT_LE(s.a.y, top.y);
    EXPECT_GT(s.brightness, 0.0f);
    EXPECT_LE(s.brightness, 1.0f);
  }
  // The foot lands within a quarter of the height of the flash (not drifting off across the map).
  const glm::vec3 foot = bolt[kBoltMainSegments - 1].b;
  EXPECT_LT(glm::length(glm::vec2(foot.x - top.x, foot.z - top.z)), 0.25f * 760.0f * 1.5f);
  const std::vector<BoltSegment> again = lightning_bolt(top, 0.0f, 42), other = lightning_bolt(top, 0.0f, 43);
  ASSERT_EQ(again.size(), bolt.size());
  for (size_t i = 0; i < bolt.size(); ++i) EXPECT_EQ(again[i].b, bolt[i].b);
  EXPECT_NE(other[kBoltMainSegments - 1].b, foot);
  EXPECT_TRUE(lightning_bolt(glm::vec3(0, 0.5f, 0), 0.0f, 1).empty());  // no height, no bolt
}

}  // namespace

#include "engine/core/json.h"

// A scripted bolt's channel comes from where the event sits in the level and where it strikes, never from the level
// file's name: the same level renders the same bolt from any folder (before, a test in a fresh temporary folder drew a
// different bolt each run).
TEST(Lightning, AScriptedBoltsShapeDoesNotDependOnTheFilesName) {
  const Json j = Json::parse(R"({"kind": "ground", "position": [0, 540, 0]})");
  const Json moved = Json::parse(R"({"kind": "ground", "position": [40, 540, 0]})");
  const LightningEvent a = lightning_event_from_json(JsonDocument(j, "/tmp/one/level.json").view());
  const LightningEvent b = lightning_event_from_json(JsonDocument(j, "/tmp/two/other.json").view());
  const LightningEvent c = lightning_event_from_json(JsonDocument(moved, "/tmp/one/level.json").view());
  EXPECT_EQ(a.seed, b.seed);
  EXPECT_NE(a.seed, c.seed);
  const auto bolt_a = lightning_bolt(a.position, 0.0f, a.seed), bolt_b = lightning_bolt(b.position, 0.0f, b.seed);
  ASSERT_EQ(bolt_a.size(), bolt_b.size());
  for (size_t i = 0; i < bolt_a.size(); ++i) EXPECT_EQ(bolt_a[i].a, bolt_b[i].a) << i;
}
