#include "modules/clouds/weather/weather_zone.h"

#include <cmath>

#include "engine/core/error.h"

namespace cumulo::clouds::weather {

bool WeatherZone::contains(glm::vec3 p) const {
  if (sphere) return glm::distance(p, center) <= radius;
  return glm::all(glm::greaterThanEqual(p, min)) && glm::all(glm::lessThanEqual(p, max));
}

float WeatherZone::volume() const {
  if (sphere) return 4.18879f * radius * radius * radius;
  const glm::vec3 e = max - min;
  return e.x * e.y * e.z;
}

WeatherZone weather_zone_from_json(const JsonView& v) {
  for (const std::string& k : v.keys())
    if (k != "name" && k != "priority" && k != "box" && k != "sphere" && k != "states")
      v.fail("unknown key \"" + k + "\" (expected name, priority, box, sphere, states)");
  WeatherZone z;
  z.name = v.get<std::string>("name", "");
  z.priority = v.get<int>("priority", 0);
  if (v.has("box") == v.has("sphere")) v.fail("expected exactly one of \"box\" and \"sphere\"");
  if (v.has("box")) {
    const JsonView b = v["box"];
    z.min = b["min"].as_vec3();
    z.max = b["max"].as_vec3();
    if (!glm::all(glm::lessThan(z.min, z.max))) b.fail("expected min < max on every axis");
  } else {
    const JsonView s = v["sphere"];
    z.sphere = true;
    z.center = s["center"].as_vec3();
    z.radius = s["radius"].as_float_in(0.01f, 1e7f);
  }
  z.states = schedule_entries_from_json(v["states"]);  // the same rules as a schedule's entries
  return z;
}

Json weather_zone_to_json(const WeatherZone& z) {
  WeatherScheduler tmp;
  tmp.schedule = z.states;
  Json j = {{"name", z.name}, {"priority", z.priority}, {"states", weather_scheduler_to_json(tmp)["schedule"]}};
  if (z.sphere) j["sphere"] = {{"center", {z.center.x, z.center.y, z.center.z}}, {"radius", z.radius}};
  else j["box"] = {{"min", {z.min.x, z.min.y, z.min.z}}, {"max", {z.max.x, z.max.y, z.max.z}}};
  return j;
}

const WeatherZone* active_zone(const ecs::World& world, glm::vec3 p) {
  const WeatherZone* best = nullptr;
  world.view<const WeatherZone>().each([&](const WeatherZone& z) {
    if (!z.contains(p)) return;
    if (!best || z.priority > best->priority ||
        (z.priority == best->priority && (z.volume() < best->volume() ||
                                          (z.volume() == best->volume() && z.name < best->name))))
      best = &z;
  });
  return best;
}

}  // namespace cumulo::clouds::weather
