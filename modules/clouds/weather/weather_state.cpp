#include "modules/clouds/weather/weather_state.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "engine/core/error.h"
#include "modules/clouds/weather/weather_fields.h"

namespace cumulo::clouds::weather {
namespace {

// Refuses keys outside the object's and requires its required ones, naming the object's JSON path.
void check_keys(const JsonView& v, const WeatherObject& o) {
  if (!v.is_object()) v.fail("expected an object");
  const std::set<std::string> allowed(o.keys.begin(), o.keys.end());
  for (const std::string& k : v.keys())
    if (!allowed.count(k)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      v.fail("unknown key \"" + k + "\" (expected one of: " + list + ")");
    }
  for (const std::string& k : o.required)
    if (!v.has(k)) v.fail("missing required key \"" + k + "\"");
}

// By hand: a path, not a value; relative to the state's file, and the PNG must exist.
void read_png(const JsonView& v, const std::filesystem::path& file, CloudMapSource& map) {
  const std::string png = v.as<std::string>();
  if (png.empty()) v.fail("expected a PNG path (relative to the state file), got an empty string");
  std::filesystem::path p = png;
  map.png = p.is_absolute() ? p : file.parent_path() / p;
  if (!std::filesystem::is_regular_file(map.png)) v.fail("no such file: " + map.png.string());
}

}  // namespace

WeatherState weather_state_from_json(const JsonView& v, const std::string& id, const std::filesystem::path& file) {
  WeatherState s;
  s.id = id;
  // Rows in file order: each object's keys are checked when its first row is reached, as before the
  // table, so a state with one mistake gets the same message.
  std::set<std::string> checked;
  auto enter = [&](const JsonView& o, const std::string& path) {
    if (checked.insert(path).second) check_keys(o, *find_weather_object(path));
  };
  enter(v, "");
  for (const WeatherField& f : weather_fields()) {
    JsonView at = v;
    size_t start = 0;
    bool present = true;
    for (size_t dot; present && (dot = f.key.find('.', start)) != std::string_view::npos; start = dot + 1) {
      const std::string part(f.key.substr(start, dot - start));
      present = at.has(part);  // an absent object was refused by its parent unless it is optional
      if (present) {
        at = at[part];
        enter(at, std::string(f.key.substr(0, dot)));
      }
    }
    const std::string name(f.key.substr(start));
    if (!present || !at.has(name)) continue;  // optional (check_keys refused a missing required key)
    if (f.by_hand()) {
      if (f.key == "cloud_map.png") read_png(at[name], file, s.cloud_map);  // "$schema" is not read
      continue;
    }
    field_from_json(f, at[name], s);
  }
  return s;
}

Json weather_state_to_json(const WeatherState& s) {
  static const WeatherState defaults;
  Json j = Json::object();
  for (const WeatherField& f : weather_fields()) {
    if (f.by_hand()) continue;
    Json value = field_json(f, s);
    if (f.rule == FieldRule::Optional && value == field_json(f, defaults)) continue;
    std::string pointer = "/" + std::string(f.key);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    j[Json::json_pointer(pointer)] = std::move(value);
  }
  if (!s.cloud_map.png.empty()) j["cloud_map"]["png"] = s.cloud_map.png.filename().string();
  return j;
}

WeatherState load_weather_state(const std::filesystem::path& file) {
  const JsonDocument doc = load_json_file(file);
  return weather_state_from_json(doc.view(), file.stem().string(), file);
}

WeatherBlend blend(const WeatherState& a, const WeatherState& b, float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  WeatherBlend out;
  WeatherState& s = out.state;
  s = t < 0.5f ? a : b;  // id, the Nearest rows, the cloud map: the nearer state
  for (const WeatherField& f : weather_fields())
    if (f.blend == FieldBlend::Lerp) field_lerp(f, a, b, t, s);
  // The Velocity rows: the velocity lerps (opposite winds pass through calm rather than an undefined direction).
  const glm::vec3 v = glm::mix(a.wind_direction * a.wind_speed, b.wind_direction * b.wind_speed, t);
  s.wind_speed = glm::length(v);
  if (s.wind_speed > 1e-6f) s.wind_direction = v / s.wind_speed;
  out.map_from = a.cloud_map;
  out.map_to = b.cloud_map;
  out.map_t = t;
  return out;
}

}  // namespace cumulo::clouds::weather
