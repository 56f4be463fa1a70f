#pragma once
// Scripted gameplay triggers (issue 9): level data says when (the viewer enters or leaves a volume, a
// named event fires, the simulation reaches a time) and what to do.
//
//   "Trigger": {"when": {"enter": {"sphere": {"center": [0, 900, 0], "radius": 600}}},   // or "exit": {...},
//                                                                                        // "event": "NAME", "time": S
//               "once": true,                                                            // default true
//               "actions": [{"do": "set_weather", "state": "storm"},
//                           {"do": "encounter", "active": true},
//                           {"do": "fire_event", "name": "stormbird_killed"},            // e.g. dissipation
//                           {"do": "strike_lightning", "position": [0, 800, 0],         // kind ground|internal,
//                            "kind": "internal", "intensity": 60, "radius": 400},        // the rest optional
//                           {"do": "set_time_of_day", "hours": 18.5},
//                           {"do": "move_cloudscape", "entity": "cloudscape", "position": [0, 0, 0],
//                            "euler_deg": [0, 30, 0], "scale": 1.0}]}
// Volumes are `box` {min, max} or `sphere` {center, radius}; the viewer is app::Viewer's Transform.
// A state named by set_weather must exist (checked when the level loads); an entity named by
// move_cloudscape must exist and hold a Cloudscape (checked at the first firing: entities may be added).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/json.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"
#include "modules/clouds/weather/level_weather.h"

namespace cumulo::clouds::gameplay {

struct TriggerVolume {
  bool sphere = false;
  glm::vec3 min{0.0f}, max{0.0f}, center{0.0f};
  float radius = 0.0f;
  bool contains(glm::vec3 p) const;
};

struct TriggerAction {
  enum class Kind { SetWeather, Encounter, FireEvent, StrikeLightning, SetTimeOfDay, MoveCloudscape } kind;
  std::string text;  // state, event or entity name
  bool flag = false;
  float number = 0.0f;   // hours (set_time_of_day), intensity (strike_lightning)
  float radius = 0.0f;   // strike_lightning
  glm::vec3 position{0.0f};
  std::optional<glm::vec3> euler_deg;
  std::optional<float> scale;
  bool has_position = false;
};

struct Trigger {
  enum class When { Enter, Exit, Event, Time } when = When::Event;
  TriggerVolume volume;
  std::string event;
  double time = 0.0;
  bool once = true;
  std::vector<TriggerAction> actions;
  // Runtime.
  bool inside = false, fired = false, primed = false;
};

Trigger trigger_from_json(const JsonView& v);
Json trigger_to_json(const Trigger& t);
void register_trigger_component(ecs::ComponentRegistry& registry);
// The weather states its set_weather actions name.
std::vector<std::string> trigger_weather_states(const Trigger& t);
// Every trigger's states with their place in the level, for weather::load_level_weather to check.
std::vector<weather::NamedState> trigger_weather_references(const ecs::World& world, const std::filesystem::path& level_file);

// Update phase (after the scripted events): fires triggers and runs their actions.
void add_trigger_system(ecs::Scheduler& s);

}  // namespace cumulo::clouds::gameplay
