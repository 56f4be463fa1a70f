// CloudGrowth (issue 26), on the ECS alone: what starts a growing cloud (its event, a weather state, the level's
// start), how far its simulation should be (steps at speed / dt, held at the spec's last step), pause and single
// steps, the reset, and bad components and specs refused naming the place.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "engine/core/error.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/game_events.h"
#include "modules/clouds/weather/weather_scheduler.h"

using namespace cumulo;
using namespace cumulo::clouds;
using namespace cumulo::clouds::gameplay;

namespace {

CloudGrowth parse(const std::string& text) {
  const JsonDocument doc = parse_json_text(text, "level.json");
  return cloud_growth_from_json(doc.view());
}

struct Sim {
  ecs::World world;
  ecs::Scheduler sched;
  ecs::Entity cloud;
  explicit Sim(CloudGrowth g) {
    add_scripted_events_system(sched);
    add_cloud_growth_system(sched);
    g.step_seconds = 10.0f;  // as a resolved spec's dt
    g.last_step = 30;
    cloud = world.create();
    world.emplace<CloudGrowth>(cloud, g);
  }
  const CloudGrowth& growth() const { return world.get<CloudGrowth>(cloud); }
  CloudGrowth& growth() { return world.get<CloudGrowth>(cloud); }
  void seconds(double s, double dt = 0.1) {
    for (int i = 0; i < int(s / dt + 0.5); ++i) sched.step(world, dt);
  }
};

TEST(CloudGrowth, ItsEventStartsItAndItStepsAtSpeedOverDtThenHolds) {
  Sim s(parse(R"({"spec": "grown/cumulonimbus.json", "event": "storm_builds", "speed": 20})"));
  s.seconds(3.0);
  EXPECT_FALSE(s.growth().running);
  EXPECT_EQ(s.growth().target_steps, 0);
  fire_event(s.world, "storm_builds");
  s.seconds(5.0);  // 100 physical s = 10 steps of 10 s (2 steps per second of play)
  EXPECT_TRUE(s.growth().running);
  EXPECT_NEAR(s.growth().target_steps, 10, 1);
  EXPECT_DOUBLE_EQ(growth_steps_per_second(s.growth()), 2.0);
  s.seconds(30.0);  // past the spec's 30 steps: held there
  EXPECT_EQ(s.growth().target_steps, 30);
  EXPECT_TRUE(s.growth().ended);
  fire_event(s.world, "storm_builds");  // a second start changes nothing once it ended
  s.seconds(1.0);
  EXPECT_EQ(s.growth().target_steps, 30);
}

TEST(CloudGrowth, AWeatherStateStartsItAndTheResetEventRestartsIt) {
  Sim s(parse(R"({"spec": "a.json", "states": ["storm"], "reset_event": "storm_clears", "speed": 10})"));
  const ecs::Entity weather = s.world.create();
  weather::WeatherScheduler w;
  w.current = "fair_cumulus";
  s.world.emplace<weather::WeatherScheduler>(weather, w);
  s.seconds(2.0);
  EXPECT_FALSE(s.growth().running);
  s.world.get<weather::WeatherScheduler>(weather).current = "storm";
  s.seconds(4.0);
  EXPECT_TRUE(s.growth().running);
  EXPECT_NEAR(s.growth().target_steps, 4, 1);
  const uint32_t generation = s.growth().generation;
  s.world.get<weather::WeatherScheduler>(weather).current = "clear";
  fire_event(s.world, "storm_clears");
  s.seconds(1.0);
  EXPECT_FALSE(s.growth().running);
  EXPECT_EQ(s.growth().target_steps, 0);
  EXPECT_EQ(s.growth().generation, generation + 1);
}

TEST(CloudGrowth, PausedItHoldsItsStepAndStepsOnceWhenAsked) {
  Sim s(parse(R"({"spec": "a.json", "start_running": true, "speed": 10})"));
  s.seconds(3.0);
  const int at = s.growth().target_steps;
  EXPECT_GE(at, 2);
  s.growth().paused = true;
  s.seconds(5.0);
  EXPECT_EQ(s.growth().target_steps, at);
  s.growth().step_once = true;
  s.seconds(1.0);
  EXPECT_EQ(s.growth().target_steps, at + 1);
  EXPECT_FALSE(s.growth().step_once);
  s.growth().paused = false;
  s.seconds(2.0);  // goes on from where the single step left it
  EXPECT_NEAR(s.growth().target_steps, at + 3, 1);
}

TEST(CloudGrowth, BadComponentsAndSpecsNameThePlace) {
  struct Bad {
    const char* text;
    const char* says;
  };
  for (const Bad& b : {Bad{R"({"event": "x"})", "member \"spec\""}, Bad{R"({"spec": "", "event": "x"})", "$.spec"},
                       Bad{R"({"spec": "a.json"})", "nothing starts"},
                       Bad{R"({"spec": "a.json", "event": "x", "speed": 0})", "$.speed"},
                       Bad{R"({"spec": "a.json", "event": "x", "sped": 1})", "unknown key \"sped\""},
                       Bad{R"({"spec": "a.json", "states": "storm"})", "$.states"},
                       Bad{R"({"spec": "a.json", "event": "x", "voxel": 0.5})", "$.voxel"}}) {
    try {
      parse(b.text);
      ADD_FAILURE() << "accepted " << b.text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("level.json"), std::string::npos) << e.what();
    }
  }
  CloudGrowth g = parse(R"({"spec": "no_such_spec.json", "event": "x"})");
  try {
    resolve_cloud_growth(g, std::filesystem::temp_directory_path());
    ADD_FAILURE() << "resolved a missing spec";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("level.json: $"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no_such_spec.json"), std::string::npos) << e.what();
  }
  // The voxel round-trips (8 m, the offline bake's, by default).
  EXPECT_FLOAT_EQ(parse(R"({"spec": "a.json", "event": "x"})").voxel, 8.0f);
  EXPECT_FLOAT_EQ(parse(cloud_growth_to_json(parse(R"({"spec": "a.json", "event": "x", "voxel": 20})")).dump()).voxel, 20.0f);
  // The committed sample spec resolves: its steps and dt.
  CloudGrowth sample = parse(R"({"spec": "grown/cumulonimbus.json", "event": "x"})");
  resolve_cloud_growth(sample, std::filesystem::path(CUMULO_SOURCE_DIR) / "content/levels/sample");
  EXPECT_GT(sample.last_step, 0);
  EXPECT_GT(sample.step_seconds, 0.0f);
}

}  // namespace
