#pragma once
// The keys of a weather state in one table (issue 22): its JSON key, type, range, how it blends and its
// editor label. The loader, blend(), the writer (weather_state_to_json, and the editor's key order when
// saving) and the editor's parameter list all walk it, and a test holds content/schemas/weather.schema.json
// to it key by key, so a new key is a member of WeatherState (its default) and one row here.
//
//   for (const WeatherField& f : weather_fields()) ...          // in the shipped files' key order
//   const WeatherField* f = find_weather_field("lighting.absorption");
//   const WeatherObject* o = find_weather_object("lighting");   // its keys, those required
#include <cstdint>
#include <glm/glm.hpp>
#include <set>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "engine/core/json.h"

namespace cumulo::clouds::weather {

struct WeatherState;

// The JSON type follows the member's: float a number, uint32_t an integer, glm::vec3 an array of 3
// numbers, std::string a string. In the order of FieldRef's alternatives.
enum class FieldType { Float, Int, Vec3, Text };
// The member a row reads and writes. A null pointer (of the key's type): the key is read and written by
// hand in weather_state.cpp, and the row only gives it its place, type and whether it is required.
using FieldRef = std::variant<float* (*)(WeatherState&), uint32_t* (*)(WeatherState&), glm::vec3* (*)(WeatherState&),
                              std::string* (*)(WeatherState&)>;

enum class FieldBlend {
  Lerp,      // a + (b - a) t (Float, Vec3)
  Nearest,   // the nearer state's (t < 0.5: from)
  Velocity,  // wind.direction x wind.speed lerped as one vector (blend() does the two together)
};

enum class FieldRule {
  Required,
  Optional,   // absent: the member's default; written only when it differs from it
  Direction,  // required; not zero, normalized on load
};

struct WeatherField {
  std::string_view key;  // dotted JSON path: "lighting.phase.forward"
  FieldRef ref;
  double min = 0.0, max = 0.0;  // the loader's range (Vec3: per component, a UI range only; Text: unused)
  FieldRule rule = FieldRule::Required;
  FieldBlend blend = FieldBlend::Nearest;
  std::string_view group, label, help;  // the editor's widget; an empty group: not shown

  FieldType type() const { return FieldType(ref.index()); }
  bool by_hand() const;
};

// In the shipped files' key order ($schema first), which the editor's save keeps.
const std::vector<WeatherField>& weather_fields();
const WeatherField* find_weather_field(std::string_view key);  // nullptr for an unknown key

// One JSON object of a state ("" the root, "cloud_map.procedural"): its keys in the files' order and
// the required ones (an object is required when it holds a required key).
struct WeatherObject {
  std::vector<std::string> keys;
  std::set<std::string> required;
};
const WeatherObject* find_weather_object(std::string_view path);  // nullptr: not an object of a state

// A member-backed row's value as JSON (a float as a number, a uint32_t as an integer...); of
// WeatherState{}: the field's default.
Json field_json(const WeatherField& f, const WeatherState& s);
// Reads `v` (the field's JSON value) into s, checking type, range and rule; fails naming v's file and path.
void field_from_json(const WeatherField& f, const JsonView& v, WeatherState& s);
// s's field = the lerp of a's and b's at t (a Lerp row).
void field_lerp(const WeatherField& f, const WeatherState& a, const WeatherState& b, float t, WeatherState& s);

}  // namespace cumulo::clouds::weather
