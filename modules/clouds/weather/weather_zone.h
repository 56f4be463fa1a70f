#pragma once
// The WeatherZone component (issue 9; 2017 talk: regional weather and small local zones): a box or
// sphere in world space with its own cycle of states and a priority. The zone holding the viewer with
// the highest priority (ties: the smaller zone) is active; entering it replaces the scheduler's cycle by
// the zone's and starts a transition at once to a randomly chosen state of the zone; leaving every zone
// returns to the scheduler's own cycle the same way (weather_scheduler.h, ZoneCycle).
//
//   "WeatherZone": {"name": "storm_coast", "priority": 1,
//                   "box": {"min": [-500, -100, -500], "max": [500, 3000, 500]},    // or
//                   "sphere": {"center": [0, 500, 0], "radius": 800},
//                   "states": [{"state": "storm", "weight": 2}, {"state": "overcast_stratus", "weight": 1}]}
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/json.h"
#include "engine/ecs/world.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds::weather {

struct WeatherZone {
  std::string name;
  int priority = 0;
  bool sphere = false;
  glm::vec3 min{0.0f}, max{0.0f};  // box
  glm::vec3 center{0.0f};          // sphere
  float radius = 0.0f;
  std::vector<ScheduleEntry> states;

  bool contains(glm::vec3 p) const;
  float volume() const;
};

WeatherZone weather_zone_from_json(const JsonView& v);
Json weather_zone_to_json(const WeatherZone& z);

// The active zone at `p` (null: none), by priority, then the smaller volume, then the name.
const WeatherZone* active_zone(const ecs::World& world, glm::vec3 p);

}  // namespace cumulo::clouds::weather
