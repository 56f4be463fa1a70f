#include "modules/clouds/weather/weather_scheduler.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/hash.h"

namespace cumulo::clouds::weather {
namespace {

float in_range(glm::vec2 r, SplitMix64& rng) { return rng.range(r.x, r.y); }

glm::vec2 seconds_range(const JsonView& v, const std::string& key, glm::vec2 fallback) {
  if (!v.has(key)) return fallback;
  const glm::vec2 r = v[key].as_vec2();
  if (!(r.x > 0.0f) || !(r.y >= r.x) || r.y > 86400.0f) v[key].fail("expected [min, max] seconds with 0 < min <= max <= 86400");
  return r;
}

}  // namespace

std::vector<ScheduleEntry> schedule_entries_from_json(const JsonView& list) {
  std::vector<ScheduleEntry> out;
  double total = 0;
  for (const JsonView& e : list.elements()) {
    for (const std::string& k : e.keys())
      if (k != "state" && k != "weight" && k != "hours") e.fail("unknown key \"" + k + "\" (expected state, weight, hours)");
    ScheduleEntry s;
    s.state = e.get<std::string>("state");
    s.weight = e.has("weight") ? e["weight"].as_float_in(0.0f, 1e6f) : 1.0f;
    if (e.has("hours")) {
      const glm::vec2 h = e["hours"].as_vec2();
      if (!(h.x >= 0.0f && h.x <= 24.0f && h.y >= 0.0f && h.y <= 24.0f))
        e["hours"].fail("expected [from, to] hours in 0..24");
      s.from_hours = h.x, s.to_hours = h.y;
    }
    total += s.weight;
    out.push_back(std::move(s));
  }
  if (out.empty()) list.fail("expected at least one entry");
  if (!(total > 0.0)) list.fail("expected a positive total weight");
  return out;
}

namespace {

Json entries_to_json(const std::vector<ScheduleEntry>& list) {
  Json out = Json::array();
  for (const ScheduleEntry& e : list) {
    Json j = {{"state", e.state}, {"weight", e.weight}};
    if (e.from_hours != 0.0f || e.to_hours != 24.0f) j["hours"] = {e.from_hours, e.to_hours};
    out.push_back(j);
  }
  return out;
}

// The encounter's cycle while active, else the zone's while the viewer is in one, else the schedule.
const std::vector<ScheduleEntry>& active_cycle(const WeatherScheduler& s) {
  if (s.encounter_active && !s.encounter.empty()) return s.encounter;
  if (!s.zone.empty() && !s.zone_states.empty()) return s.zone_states;
  return s.schedule;
}

void begin_transition(WeatherScheduler& s, const std::string& to, SplitMix64& rng) {
  s.next = to;
  s.t = 0.0f;
  s.transition_duration = in_range(s.transition_s, rng);
}

}  // namespace

bool ScheduleEntry::eligible_at(float hours) const {
  if (from_hours <= to_hours) return hours >= from_hours && hours < to_hours;
  return hours >= from_hours || hours < to_hours;  // wraps midnight
}

WeatherScheduler weather_scheduler_from_json(const JsonView& v) {
  for (const std::string& k : v.keys())
    if (k != "start" && k != "hold_s" && k != "transition_s" && k != "schedule" && k != "encounter" &&
        k != "encounter_active" && k != "lightning_volume" && k != "encounter_lightning_volume")
      v.fail("unknown key \"" + k +
             "\" (expected start, hold_s, transition_s, schedule, encounter, encounter_active, lightning_volume, "
             "encounter_lightning_volume)");
  WeatherScheduler s;
  s.schedule = schedule_entries_from_json(v["schedule"]);
  s.start = v.get<std::string>("start", s.schedule.front().state);
  s.hold_s = seconds_range(v, "hold_s", s.hold_s);
  s.transition_s = seconds_range(v, "transition_s", s.transition_s);
  if (v.has("encounter")) s.encounter = schedule_entries_from_json(v["encounter"]);
  s.encounter_active = v.get<bool>("encounter_active", false);
  if (s.encounter_active && s.encounter.empty()) v["encounter_active"].fail("true, but there is no encounter schedule");
  auto box = [&](const char* key, glm::vec3& lo, glm::vec3& hi) {
    if (!v.has(key)) return false;
    const JsonView b = v[key];
    for (const std::string& k : b.keys())
      if (k != "min" && k != "max") b.fail("unknown key \"" + k + "\" (expected min, max)");
    lo = b["min"].as_vec3();
    hi = b["max"].as_vec3();
    if (!glm::all(glm::lessThanEqual(lo, hi))) b.fail("expected min <= max on every axis");
    return true;
  };
  s.has_lightning_volume = box("lightning_volume", s.lightning_min, s.lightning_max);
  s.has_encounter_lightning_volume = box("encounter_lightning_volume", s.encounter_lightning_min, s.encounter_lightning_max);
  if (s.has_encounter_lightning_volume && s.encounter.empty())
    v["encounter_lightning_volume"].fail("given, but there is no encounter schedule");
  return s;
}

Json weather_scheduler_to_json(const WeatherScheduler& s) {
  Json j = {{"start", s.start},
            {"hold_s", {s.hold_s.x, s.hold_s.y}},
            {"transition_s", {s.transition_s.x, s.transition_s.y}},
            {"schedule", entries_to_json(s.schedule)}};
  if (!s.encounter.empty()) j["encounter"] = entries_to_json(s.encounter);
  if (s.encounter_active) j["encounter_active"] = true;
  if (s.has_lightning_volume)
    j["lightning_volume"] = {{"min", {s.lightning_min.x, s.lightning_min.y, s.lightning_min.z}},
                             {"max", {s.lightning_max.x, s.lightning_max.y, s.lightning_max.z}}};
  if (s.has_encounter_lightning_volume)
    j["encounter_lightning_volume"] = {
        {"min", {s.encounter_lightning_min.x, s.encounter_lightning_min.y, s.encounter_lightning_min.z}},
        {"max", {s.encounter_lightning_max.x, s.encounter_lightning_max.y, s.encounter_lightning_max.z}}};
  return j;
}

void check_scheduler_states(const WeatherScheduler& s, const WeatherLibrary& lib, const std::string& where) {
  lib.require(s.start, where + ": start");
  for (const ScheduleEntry& e : s.schedule) lib.require(e.state, where + ": schedule");
  for (const ScheduleEntry& e : s.encounter) lib.require(e.state, where + ": encounter");
}

const ScheduleEntry& pick_entry(const std::vector<ScheduleEntry>& entries, float hours, SplitMix64& rng) {
  double total = 0;
  for (const ScheduleEntry& e : entries)
    if (e.eligible_at(hours)) total += e.weight;
  const bool any = total > 0.0;
  if (!any)
    for (const ScheduleEntry& e : entries) total += e.weight;
  double x = double(rng.uniform()) * total;
  for (const ScheduleEntry& e : entries) {
    if (any && !e.eligible_at(hours)) continue;
    if (e.weight <= 0.0f) continue;
    if (x < e.weight) return e;
    x -= e.weight;
  }
  for (auto it = entries.rbegin(); it != entries.rend(); ++it)  // rounding: the last positive entry
    if (it->weight > 0.0f && (!any || it->eligible_at(hours))) return *it;
  return entries.back();
}

void advance(WeatherScheduler& s, float dt, float hours, uint64_t seed, const ZoneCycle& zone) {
  if (!s.started) {
    s.rng = SplitMix64{hash64("weather scheduler", seed)};
    s.current = s.start;
    s.next.clear();
    s.hold_left = in_range(s.hold_s, s.rng);
    s.started = true;
    s.encounter_was_active = s.encounter_active;
  }
  const bool zone_changed = zone.name != s.zone;
  if (zone_changed) {
    s.zone = zone.name;
    s.zone_states = zone.states ? *zone.states : std::vector<ScheduleEntry>{};
  }
  // The encounter starts or ends, or the viewer enters or leaves a zone: a transition at once.
  if (s.encounter_active != s.encounter_was_active || zone_changed) {
    s.encounter_was_active = s.encounter_active;
    if (!s.next.empty()) s.current = s.next;  // a transition under way lands where it was going
    begin_transition(s, pick_entry(active_cycle(s), hours, s.rng).state, s.rng);
  }
  if (!s.next.empty()) {
    s.t += dt / std::max(s.transition_duration, 1e-3f);
    if (s.t >= 1.0f) {
      s.current = s.next;
      s.next.clear();
      s.t = 0.0f;
      s.hold_left = in_range(s.hold_s, s.rng);
      ++s.transitions;
    }
    return;
  }
  s.hold_left -= dt;
  if (s.hold_left > 0.0f) return;
  const std::string& pick = pick_entry(active_cycle(s), hours, s.rng).state;
  if (pick == s.current) {
    s.hold_left = in_range(s.hold_s, s.rng);  // the same state again: hold on
    return;
  }
  begin_transition(s, pick, s.rng);
}

void force_state(WeatherScheduler& s, const std::string& state) {
  if (!s.started) {  // before the first step: start in it
    s.start = state;
    return;
  }
  if (!s.next.empty()) s.current = s.next;
  begin_transition(s, state, s.rng);
}

WeatherBlend weather_now(const WeatherScheduler& s, const WeatherLibrary& lib) {
  const WeatherState& a = lib.get(s.current.empty() ? s.start : s.current);
  if (s.next.empty()) return blend(a, a, 0.0f);
  // Smoothstep: a transition eases in and out.
  const float t = std::clamp(s.t, 0.0f, 1.0f);
  return blend(a, lib.get(s.next), t * t * (3.0f - 2.0f * t));
}

}  // namespace cumulo::clouds::weather
