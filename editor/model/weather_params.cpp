#include "editor/model/weather_params.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "engine/core/error.h"

namespace cumulo::editor {
namespace {

std::vector<std::string> split_path(std::string_view path) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    parts.emplace_back(path.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  for (const std::string& p : parts)
    if (p.empty()) fail("%.*s: not a dotted JSON path", int(path.size()), path.data());
  return parts;
}

std::string number_text(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A value for a message: a pasted novel in a number field is not echoed whole.
std::string shown(const Json& v) {
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

}  // namespace

// Ranges are the loader's (weather_state.cpp) and the schema's; tooltips follow weather_state.h and the
// README's "Weather states" section.
const std::vector<ParamInfo>& weather_params() {
  using K = ParamKind;
  static const std::vector<ParamInfo> params = {
      {"coverage", "Coverage", "How much of the sky the cloud map covers (0 clear, 1 overcast).", K::Float, 0, 1,
       "Clouds"},
      {"cloud_type", "Cloud type", "0 stratus, 0.5 stratocumulus, 1 cumulus: the height profile of the clouds.",
       K::Float, 0, 1, "Clouds"},
      {"precipitation", "Precipitation", "How much of the cloud mass rains: the cloud map's second channel.", K::Float,
       0, 1, "Clouds"},
      {"height_skew", "Height skew", "Cloud tops lean downwind by this fraction of their height.", K::Float, 0, 1,
       "Clouds"},
      {"anvil_bias", "Anvil bias", "Widens the tops of tall clouds into anvils.", K::Float, 0, 1, "Clouds"},
      {"voxel_density", "Voxel density", "Density multiplier of the voxel cloudscape (the near, detailed clouds).",
       K::Float, 0, 100, "Clouds"},
      {"wind.direction", "Direction", "World direction the wind blows toward; normalized on load, must not be zero.",
       K::Vec3, -1, 1, "Wind"},
      {"wind.speed", "Speed (m/s)", "Scroll speed of the noise and drift of the cloud map, in m/s.", K::Float, 0, 200,
       "Wind"},
      {"cloud_map.procedural.seed", "Seed", "Seed of the procedural cloud map (ignored when a painted map is used).",
       K::Int, 0, 4294967295.0, "Cloud map"},
      {"cloud_map.procedural.scale_km", "Scale (km)", "Size of the procedural map's largest features, in km.", K::Float,
       0.1, 1000, "Cloud map"},
      {"cloud_map.procedural.octaves", "Octaves", "Noise octaves of the procedural map: more is finer detail.", K::Int,
       1, 8, "Cloud map"},
      {"lighting.absorption", "Absorption", "Extinction per unit density, 1/m: higher is darker, denser clouds.",
       K::Float, 1e-5, 10, "Lighting"},
      {"lighting.phase.forward", "Forward phase",
       "Henyey-Greenstein eccentricity of the forward lobe (bright edges "
       "toward the sun).",
       K::Float, -0.99, 0.99, "Lighting"},
      {"lighting.phase.backward", "Backward phase",
       "Henyey-Greenstein eccentricity of the backward lobe (light "
       "scattered back toward the sun).",
       K::Float, -0.99, 0.99, "Lighting"},
      {"lighting.silver.intensity", "Silver intensity",
       "Weight of the forward lobe: the silver lining around clouds "
       "in front of the sun.",
       K::Float, 0, 1, "Lighting"},
      {"lighting.silver.spread", "Silver spread", "Widens the forward lobe: g = forward x (1 - spread).", K::Float, 0,
       1, "Lighting"},
      {"lighting.ambient", "Ambient", "Multiplier of the sky's ambient light in the clouds.", K::Float, 0, 10,
       "Lighting"},
      {"lightning.frequency_per_minute", "Lightning / min",
       "Strikes per minute the weather spawns in its lightning "
       "volume.",
       K::Float, 0, 600, "Weather"},
      {"rain.intensity", "Rain", "Intensity of the rain drawn in the 2.5D sky (0..1).", K::Float, 0, 1, "Weather"},
      {"haze", "Haze", "Scales the atmosphere's aerosol density and the height fog: x1 at 0.1, x4 at 0.4.", K::Float, 0,
       1, "Weather"},
      {"description", "Description", "A note for people; the engine ignores it.", K::Text, 0, 0, "Weather"},
  };
  return params;
}

const std::vector<std::string>& weather_param_groups() {
  static const std::vector<std::string> groups = {"Clouds", "Wind", "Cloud map", "Lighting", "Weather"};
  return groups;
}

const ParamInfo* find_param(std::string_view path) {
  for (const ParamInfo& p : weather_params())
    if (p.path == path) return &p;
  return nullptr;
}

Json get_param(const Json& state, std::string_view path) {
  const Json* at = &state;
  for (const std::string& key : split_path(path)) {
    if (!at->is_object() || !at->contains(key)) fail("%.*s: no such key in the state", int(path.size()), path.data());
    at = &(*at)[key];
  }
  return *at;
}

void set_param(Json& state, std::string_view path, const Json& value) {
  Json* at = &state;
  for (const std::string& key : split_path(path)) {
    if (at->is_null()) *at = Json::object();  // a member created on the way
    if (!at->is_object()) fail("%.*s: cannot set inside a non-object value", int(path.size()), path.data());
    at = &(*at)[key];  // creates the member (null) when missing
  }
  *at = value;
}

std::optional<std::string> check_param_value(const ParamInfo& p, const Json& value) {
  const std::string range = "[" + number_text(p.min) + ", " + number_text(p.max) + "]";
  auto out_of_range = [&](double v) -> std::optional<std::string> {
    if (std::isfinite(v) && v >= p.min && v <= p.max) return std::nullopt;
    return number_text(v) + " is out of range " + range;
  };
  switch (p.kind) {
    case ParamKind::Float:
      if (!value.is_number()) return "expected a number in " + range + ", got " + shown(value);
      return out_of_range(value.get<double>());
    case ParamKind::Int:
      if (value.is_number_float()) {
        const double d = value.get<double>();
        if (d != std::floor(d)) return "expected an integer in " + range + ", got " + shown(value);
        return out_of_range(d);
      }
      if (!value.is_number()) return "expected an integer in " + range + ", got " + shown(value);
      return value.is_number_unsigned() ? out_of_range(double(value.get<uint64_t>()))
                                        : out_of_range(double(value.get<int64_t>()));
    case ParamKind::Vec3: {
      if (!value.is_array() || value.size() != 3) return "expected an array of 3 numbers, got " + shown(value);
      for (const Json& c : value)
        if (!c.is_number() || !std::isfinite(c.get<double>()))
          return "expected an array of 3 numbers, got " + shown(value);
      return std::nullopt;  // the loader decides (it refuses a zero direction)
    }
    case ParamKind::Text:
      if (!value.is_string()) return "expected a string, got " + shown(value);
      return std::nullopt;
  }
  return std::nullopt;
}

Json normalize_param_value(const ParamInfo& p, const Json& value) {
  auto shortest = [](double d) -> Json {
    const float f = static_cast<float>(d);
    if (!std::isfinite(f)) return d;
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, f);  // shortest text that reads back as f
    *r.ptr = '\0';
    return std::strtod(buf, nullptr);
  };
  if (p.kind == ParamKind::Float && value.is_number_float()) return shortest(value.get<double>());
  if (p.kind == ParamKind::Int && value.is_number_float()) {
    const double d = value.get<double>();
    if (d == std::floor(d) && d >= 0 && d <= 4294967295.0) return uint64_t(d);
  }
  if (p.kind == ParamKind::Vec3 && value.is_array()) {
    Json out = Json::array();
    for (const Json& c : value) out.push_back(c.is_number_float() ? shortest(c.get<double>()) : c);
    return out;
  }
  return value;
}

}  // namespace cumulo::editor
