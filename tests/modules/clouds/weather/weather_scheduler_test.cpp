// The WeatherScheduler (issue 9): weighted picks (a chi-square test), time-of-day windows, holds and
// 10-30 s transitions, encounter override and release, determinism for a seed, and JSON errors.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/json.h"
#include "engine/ecs/world.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

using namespace cumulo;
using namespace cumulo::clouds::weather;

namespace {

WeatherScheduler scheduler_from(const std::string& text) {
  const JsonDocument doc = parse_json_text(text, "test.json");
  return weather_scheduler_from_json(doc.view());
}

const char* kSchedule = R"({"start": "fair_cumulus", "hold_s": [60, 120], "transition_s": [10, 30],
  "schedule": [{"state": "fair_cumulus", "weight": 3}, {"state": "clear", "weight": 1, "hours": [6, 20]},
               {"state": "storm", "weight": 0.5, "hours": [20, 4]}],
  "encounter": [{"state": "stormbird", "weight": 1}]})";

TEST(WeatherScheduler, PicksByWeightChiSquare) {
  const WeatherScheduler s = scheduler_from(kSchedule);
  // At 03:00 fair_cumulus (3) and storm (0.5, window wraps midnight) are eligible, clear is not.
  std::map<std::string, int> n;
  SplitMix64 rng{12345};
  const int picks = 35000;
  for (int i = 0; i < picks; ++i) ++n[pick_entry(s.schedule, 3.0f, rng).state];
  EXPECT_EQ(n["clear"], 0);
  const double expect_fair = picks * 3.0 / 3.5, expect_storm = picks * 0.5 / 3.5;
  const double chi2 = (n["fair_cumulus"] - expect_fair) * (n["fair_cumulus"] - expect_fair) / expect_fair +
                      (n["storm"] - expect_storm) * (n["storm"] - expect_storm) / expect_storm;
  std::printf("  03:00: fair_cumulus %d, storm %d of %d; chi-square %.2f (1 dof, p = 0.001 at 10.83)\n",
              n["fair_cumulus"], n["storm"], picks, chi2);
  EXPECT_LT(chi2, 10.83);
  // At noon: fair_cumulus and clear, 3 : 1.
  n.clear();
  for (int i = 0; i < picks; ++i) ++n[pick_entry(s.schedule, 12.0f, rng).state];
  EXPECT_EQ(n["storm"], 0);
  const double ef = picks * 0.75, ec = picks * 0.25;
  const double chi2b = (n["fair_cumulus"] - ef) * (n["fair_cumulus"] - ef) / ef + (n["clear"] - ec) * (n["clear"] - ec) / ec;
  EXPECT_LT(chi2b, 10.83);
}

TEST(WeatherScheduler, WindowsWrapMidnight) {
  ScheduleEntry e{"storm", 1.0f, 20.0f, 4.0f};
  EXPECT_TRUE(e.eligible_at(23.0f));
  EXPECT_TRUE(e.eligible_at(2.0f));
  EXPECT_FALSE(e.eligible_at(12.0f));
  ScheduleEntry day{"clear", 1.0f, 6.0f, 20.0f};
  EXPECT_TRUE(day.eligible_at(6.0f));
  EXPECT_FALSE(day.eligible_at(20.0f));
}

// Runs `seconds` of 1/60 s steps at `hours`; returns the sequence of (time, from, to) transition starts.
std::vector<std::string> run(WeatherScheduler& s, double seconds, float hours, uint64_t seed) {
  std::vector<std::string> starts;
  const float dt = 1.0f / 60.0f;
  for (int i = 0; i < int(seconds * 60.0); ++i) {
    const bool was = !s.next.empty();
    advance(s, dt, hours, seed);
    if (!was && !s.next.empty()) starts.push_back(std::to_string(i) + ":" + s.current + "->" + s.next);
  }
  return starts;
}

TEST(WeatherScheduler, HoldsThenTransitionsOver10To30Seconds) {
  WeatherScheduler s = scheduler_from(kSchedule);
  advance(s, 1.0f / 60.0f, 12.0f, 7);
  EXPECT_EQ(s.current, "fair_cumulus");
  EXPECT_TRUE(s.next.empty());
  EXPECT_GE(s.hold_left, 59.0f);
  EXPECT_LE(s.hold_left, 120.0f);
  // Until the first transition starts: the hold was 60..120 s.
  int steps = 0;
  while (s.next.empty() && steps < 3600 * 60) advance(s, 1.0f / 60.0f, 12.0f, 7), ++steps;  // a pick may repeat the state
  EXPECT_GE(steps, 58 * 60);
  ASSERT_FALSE(s.next.empty());
  EXPECT_GE(s.transition_duration, 10.0f);
  EXPECT_LE(s.transition_duration, 30.0f);
  const std::string to = s.next;
  int t_steps = 0;
  float last_t = -1.0f;
  while (!s.next.empty()) {
    EXPECT_GE(s.t, last_t);
    last_t = s.t;
    advance(s, 1.0f / 60.0f, 12.0f, 7);
    ++t_steps;
  }
  EXPECT_EQ(s.current, to);
  EXPECT_NEAR(t_steps / 60.0, s.transition_duration, 0.1);  // `transition_duration` of the finished one
  EXPECT_EQ(s.transitions, 1u);
}

TEST(WeatherScheduler, EncounterOverridesAndReleases) {
  WeatherScheduler s = scheduler_from(kSchedule);
  run(s, 5.0, 12.0f, 3);
  s.encounter_active = true;
  advance(s, 1.0f / 60.0f, 12.0f, 3);
  EXPECT_EQ(s.next, "stormbird");  // at once, not after the hold
  run(s, 31.0, 12.0f, 3);
  EXPECT_EQ(s.current, "stormbird");
  for (int k = 0; k < 3; ++k) {  // the encounter cycle holds stormbird: its only entry
    run(s, 200.0, 12.0f, 3);
    EXPECT_EQ(s.current, "stormbird");
  }
  s.encounter_active = false;
  advance(s, 1.0f / 60.0f, 12.0f, 3);
  ASSERT_FALSE(s.next.empty());  // the regional cycle resumes at once
  EXPECT_NE(s.next, "stormbird");
}

TEST(WeatherScheduler, SameSeedSameWeatherOtherSeedOther) {
  WeatherScheduler a = scheduler_from(kSchedule), b = scheduler_from(kSchedule), c = scheduler_from(kSchedule);
  const auto ra = run(a, 7200.0, 12.0f, 42), rb = run(b, 7200.0, 12.0f, 42), rc = run(c, 7200.0, 12.0f, 43);
  EXPECT_GT(ra.size(), 5u);
  EXPECT_EQ(ra, rb);
  EXPECT_NE(ra, rc);
}

TEST(WeatherScheduler, BadJsonNamesThePlace) {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      scheduler_from(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  auto has = [](const std::string& m, const std::string& w) { return m.find(w) != std::string::npos; };
  std::string m = error_of(R"({"schedule": [{"state": "clear"}], "holds": [1, 2]})");
  EXPECT_TRUE(has(m, "test.json") && has(m, "unknown key \"holds\"")) << m;
  m = error_of(R"({"schedule": []})");
  EXPECT_TRUE(has(m, "$.schedule") && has(m, "at least one")) << m;
  m = error_of(R"({"schedule": [{"state": "clear", "weight": 0}]})");
  EXPECT_TRUE(has(m, "positive total weight")) << m;
  m = error_of(R"({"schedule": [{"state": "clear", "hours": [6, 25]}]})");
  EXPECT_TRUE(has(m, "$.schedule[0].hours") && has(m, "0..24")) << m;
  m = error_of(R"({"schedule": [{"state": "clear"}], "transition_s": [30, 10]})");
  EXPECT_TRUE(has(m, "$.transition_s")) << m;
  m = error_of(R"({"schedule": [{"state": "clear"}], "encounter_active": true})");
  EXPECT_TRUE(has(m, "$.encounter_active") && has(m, "no encounter")) << m;
  // States the library does not have.
  const WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
  const WeatherScheduler bad = scheduler_from(R"({"schedule": [{"state": "clear"}, {"state": "hail"}]})");
  try {
    check_scheduler_states(bad, lib, "level.json: entity \"weather\"");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(has(msg, "level.json") && has(msg, "hail") && has(msg, "fair_cumulus")) << msg;
  }
}

TEST(WeatherScheduler, WeatherNowBlendsAlongTheTransition) {
  const WeatherLibrary lib = WeatherLibrary::load(WeatherLibrary::default_folder());
  WeatherScheduler s = scheduler_from(kSchedule);
  s.current = "clear";
  s.next = "storm";
  s.started = true;
  s.t = 0.5f;
  const WeatherState mid = weather_now(s, lib).state;
  const float a = lib.get("clear").voxel_density, b = lib.get("storm").voxel_density;
  EXPECT_NEAR(mid.voxel_density, 0.5f * (a + b), 1e-5f);  // smoothstep(0.5) = 0.5
  s.t = 0.1f;
  EXPECT_LT(weather_now(s, lib).state.voxel_density, a + 0.1f * (b - a));  // eased in
  s.next.clear();
  EXPECT_FLOAT_EQ(weather_now(s, lib).state.voxel_density, a);
}

}  // namespace

namespace {

WeatherZone zone_from(const std::string& text) {
  const JsonDocument doc = parse_json_text(text, "zone.json");
  return weather_zone_from_json(doc.view());
}

TEST(WeatherZone, EnteringReplacesTheCycleAtOnceAndLeavingRestoresIt) {
  WeatherScheduler s = scheduler_from(kSchedule);
  const WeatherZone storm_coast = zone_from(R"({"name": "storm_coast", "box": {"min": [0, 0, 0], "max": [100, 100, 100]},
                                               "states": [{"state": "storm", "weight": 1}]})");
  const float dt = 1.0f / 60.0f;
  for (int i = 0; i < 60; ++i) advance(s, dt, 12.0f, 5);
  EXPECT_EQ(s.current, "fair_cumulus");
  EXPECT_TRUE(s.next.empty());
  advance(s, dt, 12.0f, 5, ZoneCycle{storm_coast.name, &storm_coast.states});  // entering
  EXPECT_EQ(s.next, "storm");  // the transition starts at once
  for (int i = 0; i < 60 * 40; ++i) advance(s, dt, 12.0f, 5, ZoneCycle{storm_coast.name, &storm_coast.states});
  EXPECT_EQ(s.current, "storm");
  for (int i = 0; i < 60 * 400; ++i) advance(s, dt, 12.0f, 5, ZoneCycle{storm_coast.name, &storm_coast.states});
  EXPECT_EQ(s.current, "storm");  // the zone's only state, however long the stay
  advance(s, dt, 12.0f, 5);        // leaving
  ASSERT_FALSE(s.next.empty());
  EXPECT_NE(s.next, "storm");      // a pick of the scheduler's own cycle (which has storm only at night)
}

TEST(WeatherZone, TheHighestPriorityThenTheSmallestZoneHoldingThePointIsActive) {
  ecs::World w;
  auto add = [&](const std::string& text) { w.emplace<WeatherZone>(w.create(), zone_from(text)); };
  add(R"({"name": "region", "box": {"min": [-1000, -1000, -1000], "max": [1000, 1000, 1000]}, "states": [{"state": "clear"}]})");
  add(R"({"name": "cove", "sphere": {"center": [100, 0, 0], "radius": 50}, "states": [{"state": "storm"}]})");
  add(R"({"name": "lair", "priority": 2, "sphere": {"center": [500, 0, 0], "radius": 400}, "states": [{"state": "stormbird"}]})");
  EXPECT_EQ(active_zone(w, {0, 0, 0})->name, "region");
  EXPECT_EQ(active_zone(w, {100, 10, 0})->name, "cove");    // smaller, same priority
  EXPECT_EQ(active_zone(w, {150, 0, 0})->name, "lair");     // priority wins over size
  EXPECT_EQ(active_zone(w, {5000, 0, 0}), nullptr);
}

TEST(WeatherZone, BadZonesNameThePlace) {
  auto error_of = [](const std::string& text) -> std::string {
    try {
      zone_from(text);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  std::string m = error_of(R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "sphere": {"center": [0, 0, 0], "radius": 1},
                               "states": [{"state": "clear"}]})");
  EXPECT_NE(m.find("exactly one of"), std::string::npos) << m;
  m = error_of(R"({"box": {"min": [0, 5, 0], "max": [1, 1, 1]}, "states": [{"state": "clear"}]})");
  EXPECT_NE(m.find("$.box"), std::string::npos) << m;
  m = error_of(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "states": []})");
  EXPECT_NE(m.find("$.states"), std::string::npos) << m;
  m = error_of(R"({"sphere": {"center": [0, 0, 0], "radius": 1}, "states": [{"state": "clear"}], "shape": "box"})");
  EXPECT_NE(m.find("unknown key \"shape\""), std::string::npos) << m;
}

}  // namespace
