#pragma once
// Weather states (issue 9; 2017 talk, seed 001, and 2015, seed 004): one JSON file per state in
// content/weather/, checked against content/schemas/weather.schema.json's rules by the loader, which
// names the file, the JSON path and what was expected in every error. The keys are stable: the editor
// addresses them as dotted paths (`lighting.absorption`). Any two states blend parameter by parameter.
//
//   {"coverage": 0.45,                          // 0..1: how much of the sky the cloud map covers
//    "cloud_type": 1.0,                         // 0 stratus .. 0.5 stratocumulus .. 1 cumulus
//    "precipitation": 0.0,                      // 0..1: the cloud map's second channel
//    "wind": {"direction": [1, 0, 0.3], "speed": 4},   // noise scroll and cloud-map drift, m/s
//    "height_skew": 0.2,                        // 0..1: tops lean downwind by this fraction of their height
//    "anvil_bias": 0.0,                         // 0..1: widens the tops of tall clouds
//    "cloud_map": {"procedural": {"seed": 1, "scale_km": 8, "octaves": 4}, "png": "map.png"},
//                                               // the 2.5D sky's map: procedural, or a painted PNG
//                                               // (relative to the state file) that overrides it
//    "voxel_density": 1.0,                      // density multiplier of the voxel cloudscape
//    "lighting": {"absorption": 0.05,           // extinction per unit density, 1/m
//                 "phase": {"forward": 0.8, "backward": -0.3},  // HG eccentricities of the two lobes
//                 "silver": {"intensity": 0.7, "spread": 0.0},  // forward lobe weight; spread widens it
//                 "ambient": 1.0},              // sky ambient multiplier
//    "lightning": {"frequency_per_minute": 0},  // strikes spawned by the weather
//    "rain": {"intensity": 0},                  // 0..1
//    "haze": 0.1,                               // 0..1
//    "description": "..."}                      // optional, for people
// Every key but `description` and `cloud_map.png` is required, so a state never depends on defaults
// hidden in code; unknown keys are refused (a typo would otherwise be silently ignored). The keys, their
// ranges and how they blend are the rows of weather_fields.h; the defaults are the members' below.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/json.h"

namespace cumulo::clouds::weather {

// A cloud map being painted in the editor (RGBA8, top row first, the PNG's layout): it overrides the
// PNG and the procedural map until saved. Immutable once shared: each change is a new object, so the
// renderer sees a different pointer and uploads it again.
struct PaintedCloudMap {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

struct CloudMapSource {
  uint32_t seed = 1;
  float scale_km = 8.0f;  // size of the map's largest features
  uint32_t octaves = 4;
  std::filesystem::path png;  // painted map (absolute once loaded); empty: procedural
  std::shared_ptr<const PaintedCloudMap> painted;  // the editor's unsaved painting (never in JSON)
  bool operator==(const CloudMapSource&) const = default;
};

struct WeatherLighting {
  float absorption = 0.05f;
  float phase_forward = 0.8f, phase_backward = -0.3f;
  float silver_intensity = 0.7f, silver_spread = 0.0f;
  float ambient = 1.0f;
  bool operator==(const WeatherLighting&) const = default;
};

struct WeatherState {
  std::string id;  // the file's stem
  std::string description;
  float coverage = 0.0f, cloud_type = 1.0f, precipitation = 0.0f;
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};  // unit
  float wind_speed = 0.0f;
  float height_skew = 0.0f, anvil_bias = 0.0f;
  CloudMapSource cloud_map;
  float voxel_density = 1.0f;
  // The Envelope method's orographic clouds (OrographicClouds): x their coverage and density (optional: 1, 1).
  float envelope_coverage = 1.0f, envelope_density = 1.0f;
  WeatherLighting lighting;
  float lightning_per_minute = 0.0f;
  float rain_intensity = 0.0f;
  float haze = 0.0f;
  bool operator==(const WeatherState&) const = default;
};

// From a state's JSON (`v` is its root); `file` resolves cloud_map.png. Throws cumulo::Error naming the
// file and JSON path.
WeatherState weather_state_from_json(const JsonView& v, const std::string& id, const std::filesystem::path& file);
Json weather_state_to_json(const WeatherState& s);  // the same keys; png relative to nothing (as stored)
WeatherState load_weather_state(const std::filesystem::path& file);

// A blend of two states at t in 0..1 (the talk's lerp, parameter by parameter). The cloud map cannot be
// lerped: it cross-fades, so the blend keeps both sources and the weight of `to`.
struct WeatherBlend {
  WeatherState state;  // numbers lerped; cloud_map = the nearer source
  CloudMapSource map_from, map_to;
  float map_t = 0.0f;
};
WeatherBlend blend(const WeatherState& from, const WeatherState& to, float t);

}  // namespace cumulo::clouds::weather
