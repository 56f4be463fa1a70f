#include "modules/clouds/weather/weather_state.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "engine/core/error.h"

namespace cumulo::clouds::weather {
namespace {

// Refuses keys outside `allowed` and requires those in `required`, naming the object's JSON path.
void check_keys(const JsonView& v, const std::set<std::string>& allowed, const std::set<std::string>& required) {
  if (!v.is_object()) v.fail("expected an object");
  for (const std::string& k : v.keys())
    if (!allowed.count(k)) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      v.fail("unknown key \"" + k + "\" (expected one of: " + list + ")");
    }
  for (const std::string& k : required)
    if (!v.has(k)) v.fail("missing required key \"" + k + "\"");
}

float in(const JsonView& v, const std::string& key, float lo, float hi) { return v[key].as_float_in(lo, hi); }

}  // namespace

WeatherState weather_state_from_json(const JsonView& v, const std::string& id, const std::filesystem::path& file) {
  static const std::set<std::string> kTop = {"coverage", "cloud_type", "precipitation", "wind", "height_skew",
                                             "anvil_bias", "cloud_map", "voxel_density", "lighting", "lightning",
                                             "rain", "haze", "description", "$schema"};
  std::set<std::string> required = kTop;
  required.erase("description");
  required.erase("$schema");
  check_keys(v, kTop, required);
  WeatherState s;
  s.id = id;
  s.description = v.get<std::string>("description", "");
  s.coverage = in(v, "coverage", 0.0f, 1.0f);
  s.cloud_type = in(v, "cloud_type", 0.0f, 1.0f);
  s.precipitation = in(v, "precipitation", 0.0f, 1.0f);
  const JsonView wind = v["wind"];
  check_keys(wind, {"direction", "speed"}, {"direction", "speed"});
  const glm::vec3 dir = wind["direction"].as_vec3();
  if (!(glm::length(dir) > 1e-6f)) wind["direction"].fail("expected a non-zero direction");
  s.wind_direction = glm::normalize(dir);
  s.wind_speed = in(wind, "speed", 0.0f, 200.0f);
  s.height_skew = in(v, "height_skew", 0.0f, 1.0f);
  s.anvil_bias = in(v, "anvil_bias", 0.0f, 1.0f);
  const JsonView map = v["cloud_map"];
  check_keys(map, {"procedural", "png"}, {"procedural"});
  const JsonView proc = map["procedural"];
  check_keys(proc, {"seed", "scale_km", "octaves"}, {"seed", "scale_km", "octaves"});
  s.cloud_map.seed = proc["seed"].as<uint32_t>();
  s.cloud_map.scale_km = in(proc, "scale_km", 0.1f, 1000.0f);
  s.cloud_map.octaves = proc["octaves"].as<uint32_t>();
  if (s.cloud_map.octaves < 1 || s.cloud_map.octaves > 8) proc["octaves"].fail("expected 1..8 octaves");
  if (map.has("png")) {
    const std::string png = map["png"].as<std::string>();
    if (png.empty()) map["png"].fail("expected a PNG path (relative to the state file), got an empty string");
    std::filesystem::path p = png;
    s.cloud_map.png = p.is_absolute() ? p : file.parent_path() / p;
    if (!std::filesystem::is_regular_file(s.cloud_map.png))
      map["png"].fail("no such file: " + s.cloud_map.png.string());
  }
  s.voxel_density = in(v, "voxel_density", 0.0f, 100.0f);
  const JsonView light = v["lighting"];
  check_keys(light, {"absorption", "phase", "silver", "ambient"}, {"absorption", "phase", "silver", "ambient"});
  s.lighting.absorption = in(light, "absorption", 1e-5f, 10.0f);
  const JsonView phase = light["phase"];
  check_keys(phase, {"forward", "backward"}, {"forward", "backward"});
  s.lighting.phase_forward = in(phase, "forward", -0.99f, 0.99f);
  s.lighting.phase_backward = in(phase, "backward", -0.99f, 0.99f);
  const JsonView silver = light["silver"];
  check_keys(silver, {"intensity", "spread"}, {"intensity", "spread"});
  s.lighting.silver_intensity = in(silver, "intensity", 0.0f, 1.0f);
  s.lighting.silver_spread = in(silver, "spread", 0.0f, 1.0f);
  s.lighting.ambient = in(light, "ambient", 0.0f, 10.0f);
  const JsonView lightning = v["lightning"];
  check_keys(lightning, {"frequency_per_minute"}, {"frequency_per_minute"});
  s.lightning_per_minute = in(lightning, "frequency_per_minute", 0.0f, 600.0f);
  const JsonView rain = v["rain"];
  check_keys(rain, {"intensity"}, {"intensity"});
  s.rain_intensity = in(rain, "intensity", 0.0f, 1.0f);
  s.haze = in(v, "haze", 0.0f, 1.0f);
  return s;
}

Json weather_state_to_json(const WeatherState& s) {
  Json map = {{"procedural", {{"seed", s.cloud_map.seed}, {"scale_km", s.cloud_map.scale_km}, {"octaves", s.cloud_map.octaves}}}};
  if (!s.cloud_map.png.empty()) map["png"] = s.cloud_map.png.filename().string();
  Json j = {{"coverage", s.coverage},
            {"cloud_type", s.cloud_type},
            {"precipitation", s.precipitation},
            {"wind", {{"direction", {s.wind_direction.x, s.wind_direction.y, s.wind_direction.z}}, {"speed", s.wind_speed}}},
            {"height_skew", s.height_skew},
            {"anvil_bias", s.anvil_bias},
            {"cloud_map", map},
            {"voxel_density", s.voxel_density},
            {"lighting",
             {{"absorption", s.lighting.absorption},
              {"phase", {{"forward", s.lighting.phase_forward}, {"backward", s.lighting.phase_backward}}},
              {"silver", {{"intensity", s.lighting.silver_intensity}, {"spread", s.lighting.silver_spread}}},
              {"ambient", s.lighting.ambient}}},
            {"lightning", {{"frequency_per_minute", s.lightning_per_minute}}},
            {"rain", {{"intensity", s.rain_intensity}}},
            {"haze", s.haze}};
  if (!s.description.empty()) j["description"] = s.description;
  return j;
}

WeatherState load_weather_state(const std::filesystem::path& file) {
  const JsonDocument doc = load_json_file(file);
  return weather_state_from_json(doc.view(), file.stem().string(), file);
}

WeatherBlend blend(const WeatherState& a, const WeatherState& b, float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  auto mix = [t](float x, float y) { return x + (y - x) * t; };
  WeatherBlend out;
  WeatherState& s = out.state;
  s = t < 0.5f ? a : b;  // id, description, cloud map: the nearer state
  s.coverage = mix(a.coverage, b.coverage);
  s.cloud_type = mix(a.cloud_type, b.cloud_type);
  s.precipitation = mix(a.precipitation, b.precipitation);
  // Wind: the velocity lerps (opposite winds pass through calm rather than an undefined direction).
  const glm::vec3 v = glm::mix(a.wind_direction * a.wind_speed, b.wind_direction * b.wind_speed, t);
  s.wind_speed = glm::length(v);
  if (s.wind_speed > 1e-6f) s.wind_direction = v / s.wind_speed;
  s.height_skew = mix(a.height_skew, b.height_skew);
  s.anvil_bias = mix(a.anvil_bias, b.anvil_bias);
  s.voxel_density = mix(a.voxel_density, b.voxel_density);
  s.lighting.absorption = mix(a.lighting.absorption, b.lighting.absorption);
  s.lighting.phase_forward = mix(a.lighting.phase_forward, b.lighting.phase_forward);
  s.lighting.phase_backward = mix(a.lighting.phase_backward, b.lighting.phase_backward);
  s.lighting.silver_intensity = mix(a.lighting.silver_intensity, b.lighting.silver_intensity);
  s.lighting.silver_spread = mix(a.lighting.silver_spread, b.lighting.silver_spread);
  s.lighting.ambient = mix(a.lighting.ambient, b.lighting.ambient);
  s.lightning_per_minute = mix(a.lightning_per_minute, b.lightning_per_minute);
  s.rain_intensity = mix(a.rain_intensity, b.rain_intensity);
  s.haze = mix(a.haze, b.haze);
  out.map_from = a.cloud_map;
  out.map_to = b.cloud_map;
  out.map_t = t;
  return out;
}

}  // namespace cumulo::clouds::weather
