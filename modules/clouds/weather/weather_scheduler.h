#pragma once
// The WeatherScheduler component (issue 9; 2017 talk: a schedule of weather states that the game
// transitions between): holds a state for a while, then picks the next one by weighted chance among
// the entries whose time-of-day window holds the current hour, and blends to it over 10-30 s. The
// viewer's WeatherZone (weather_zone.h) replaces the cycle while the viewer is in it, and an encounter
// schedule (a boss fight's cycle) replaces both while it is active; each change starts a transition at
// once to a fresh pick of the new cycle. Deterministic given the seed (the run's `--seed`).
//
//   "WeatherScheduler": {"start": "fair_cumulus",
//                        "hold_s": [60, 180],          // how long a state holds before the next pick
//                        "transition_s": [10, 30],     // how long a transition takes
//                        "schedule": [{"state": "clear", "weight": 1, "hours": [6, 20]},
//                                     {"state": "fair_cumulus", "weight": 3},
//                                     {"state": "storm", "weight": 0.5, "hours": [12, 19]}],
//                        "encounter": [{"state": "stormbird", "weight": 1}],
//                        "encounter_active": false,
//                        "lightning_volume": {"min": [-2048, 600, -2048], "max": [2048, 900, 2048]},
//                        "encounter_lightning_volume": {"min": [800, 650, -900], "max": [1200, 1000, -500]}}
// While the encounter is active its lightning strikes in encounter_lightning_volume (the boss's storm
// cloud) when there is one, else in lightning_volume.
// `hours` [from, to) may wrap midnight ([20, 4]); without it an entry is eligible all day.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/json.h"
#include "engine/core/random.h"
#include "modules/clouds/weather/weather_library.h"

namespace cumulo::clouds::weather {

struct ScheduleEntry {
  std::string state;
  float weight = 1.0f;
  float from_hours = 0.0f, to_hours = 24.0f;
  bool eligible_at(float hours) const;
};

struct WeatherScheduler {
  std::string start;
  glm::vec2 hold_s{60.0f, 180.0f};
  glm::vec2 transition_s{10.0f, 30.0f};
  std::vector<ScheduleEntry> schedule, encounter;
  bool encounter_active = false;
  // Where the weather's lightning (lightning.frequency_per_minute) strikes: a world box; none: nowhere.
  bool has_lightning_volume = false;
  glm::vec3 lightning_min{0.0f}, lightning_max{0.0f};
  bool has_encounter_lightning_volume = false;
  glm::vec3 encounter_lightning_min{0.0f}, encounter_lightning_max{0.0f};

  // Runtime (not in the level file).
  std::string current, next;  // next empty: holding `current`
  float t = 0.0f;             // transition progress 0..1
  float transition_duration = 0.0f, hold_left = 0.0f;
  SplitMix64 rng;
  bool started = false, encounter_was_active = false;
  std::string zone;                        // the active WeatherZone's name ("" none)
  std::vector<ScheduleEntry> zone_states;  // its cycle
  uint32_t transitions = 0;   // completed
};

WeatherScheduler weather_scheduler_from_json(const JsonView& v);
// A list of {"state", "weight", "hours"} entries (a schedule, an encounter, a zone's states).
std::vector<ScheduleEntry> schedule_entries_from_json(const JsonView& list);
Json weather_scheduler_to_json(const WeatherScheduler& s);
// Every state the scheduler names exists in `lib` (throws naming `where` and the state otherwise).
void check_scheduler_states(const WeatherScheduler& s, const WeatherLibrary& lib, const std::string& where);

// The weighted pick among the entries eligible at `hours` (all entries when none is); advances `rng`.
const ScheduleEntry& pick_entry(const std::vector<ScheduleEntry>& entries, float hours, SplitMix64& rng);
// One simulation step: seeds the stream on the first call, counts down the hold, starts and finishes
// transitions, switches to or from the encounter cycle at once when encounter_active changes.
// The viewer's zone this step (weather_zone.h): its name ("" for none) and its states.
struct ZoneCycle {
  std::string name;
  const std::vector<ScheduleEntry>* states = nullptr;
};
void advance(WeatherScheduler& s, float dt, float hours, uint64_t seed, const ZoneCycle& zone = {});
// A script's "set the weather": a transition to `state` at once (within the transition_s range); the
// cycle then goes on from it.
void force_state(WeatherScheduler& s, const std::string& state);
// The weather now: current, or the blend toward next.
WeatherBlend weather_now(const WeatherScheduler& s, const WeatherLibrary& lib);

}  // namespace cumulo::clouds::weather
