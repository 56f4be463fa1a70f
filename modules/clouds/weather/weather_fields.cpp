#include "modules/clouds/weather/weather_fields.h"

#include <algorithm>
#include <map>

#include "engine/core/error.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds::weather {
namespace {

// The member at the end of a chain of pointers to members: at<&WeatherState::lighting, &WeatherLighting::ambient>.
template <auto... M>
auto* at(WeatherState& s) {
  // clang-format off
  return &(s .* ... .* M);
  // clang-format on
}

// Rows read and written by hand (weather_state.cpp): "$schema" names the schema an editor checks the file
// against and is no part of the weather; "cloud_map.png" is a path, resolved against the state's file
// (which must exist) and written back as a file name.
constexpr std::string* (*kByHand)(WeatherState&) = nullptr;

template <typename T>
T& member(const WeatherField& f, WeatherState& s) {
  return *std::get<T* (*)(WeatherState&)>(f.ref)(s);
}
// The accessors take a mutable state so one pointer serves both ways; reading through it changes nothing.
template <typename T>
const T& member(const WeatherField& f, const WeatherState& s) {
  return member<T>(f, const_cast<WeatherState&>(s));
}

}  // namespace

bool WeatherField::by_hand() const {
  return std::visit([](auto p) { return p == nullptr; }, ref);
}

// Help texts follow weather_state.h and the README's "Weather states" section.
const std::vector<WeatherField>& weather_fields() {
  using R = FieldRule;
  using B = FieldBlend;
  using S = WeatherState;
  static const std::vector<WeatherField> fields = {
      {"$schema", kByHand, 0, 0, R::Optional},
      {"coverage", &at<&S::coverage>, 0, 1, R::Required, B::Lerp, "Clouds", "Coverage",
       "How much of the sky the cloud map covers (0 clear, 1 overcast)."},
      {"cloud_type", &at<&S::cloud_type>, 0, 1, R::Required, B::Lerp, "Clouds", "Cloud type",
       "0 stratus, 0.5 stratocumulus, 1 cumulus: the height profile of the clouds."},
      {"precipitation", &at<&S::precipitation>, 0, 1, R::Required, B::Lerp, "Clouds", "Precipitation",
       "How much of the cloud mass rains: the cloud map's second channel."},
      {"wind.direction", &at<&S::wind_direction>, -1, 1, R::Direction, B::Velocity, "Wind", "Direction",
       "World direction the wind blows toward; normalized on load, must not be zero."},
      {"wind.speed", &at<&S::wind_speed>, 0, 200, R::Required, B::Velocity, "Wind", "Speed (m/s)",
       "Scroll speed of the noise and drift of the cloud map, in m/s."},
      {"height_skew", &at<&S::height_skew>, 0, 1, R::Required, B::Lerp, "Clouds", "Height skew",
       "Cloud tops lean downwind by this fraction of their height."},
      {"anvil_bias", &at<&S::anvil_bias>, 0, 1, R::Required, B::Lerp, "Clouds", "Anvil bias",
       "Widens the tops of tall clouds into anvils."},
      // The cloud map cross-fades as a whole (WeatherBlend::map_from/map_to): its numbers are not lerped.
      {"cloud_map.procedural.seed", &at<&S::cloud_map, &CloudMapSource::seed>, 0, 4294967295.0, R::Required, B::Nearest,
       "Cloud map", "Seed", "Seed of the procedural cloud map (ignored when a painted map is used)."},
      {"cloud_map.procedural.scale_km", &at<&S::cloud_map, &CloudMapSource::scale_km>, 0.1, 1000, R::Required,
       B::Nearest, "Cloud map", "Scale (km)", "Size of the procedural map's largest features, in km."},
      {"cloud_map.procedural.octaves", &at<&S::cloud_map, &CloudMapSource::octaves>, 1, 8, R::Required, B::Nearest,
       "Cloud map", "Octaves", "Noise octaves of the procedural map: more is finer detail."},
      {"cloud_map.png", kByHand, 0, 0, R::Optional},
      {"voxel_density", &at<&S::voxel_density>, 0, 100, R::Required, B::Lerp, "Clouds", "Voxel density",
       "Density multiplier of the voxel cloudscape (the near, detailed clouds)."},
      {"envelope.coverage", &at<&S::envelope_coverage>, 0, 1, R::Optional, B::Lerp, "Envelope clouds", "Coverage",
       "Multiplies the orographic clouds' coverage (caps, banks, fog; OrographicClouds): 0 none, 1 as authored."},
      {"envelope.density", &at<&S::envelope_density>, 0, 100, R::Optional, B::Lerp, "Envelope clouds", "Density",
       "Multiplies the orographic clouds' density."},
      {"lighting.absorption", &at<&S::lighting, &WeatherLighting::absorption>, 1e-5, 10, R::Required, B::Lerp,
       "Lighting", "Absorption", "Extinction per unit density, 1/m: higher is darker, denser clouds."},
      {"lighting.phase.forward", &at<&S::lighting, &WeatherLighting::phase_forward>, -0.99, 0.99, R::Required, B::Lerp,
       "Lighting", "Forward phase",
       "Henyey-Greenstein eccentricity of the forward lobe (bright edges toward the sun)."},
      {"lighting.phase.backward", &at<&S::lighting, &WeatherLighting::phase_backward>, -0.99, 0.99, R::Required,
       B::Lerp, "Lighting", "Backward phase",
       "Henyey-Greenstein eccentricity of the backward lobe (light scattered back toward the sun)."},
      {"lighting.silver.intensity", &at<&S::lighting, &WeatherLighting::silver_intensity>, 0, 1, R::Required, B::Lerp,
       "Lighting", "Silver intensity",
       "Weight of the forward lobe: the silver lining around clouds in front of the sun."},
      {"lighting.silver.spread", &at<&S::lighting, &WeatherLighting::silver_spread>, 0, 1, R::Required, B::Lerp,
       "Lighting", "Silver spread", "Widens the forward lobe: g = forward x (1 - spread)."},
      {"lighting.ambient", &at<&S::lighting, &WeatherLighting::ambient>, 0, 10, R::Required, B::Lerp, "Lighting",
       "Ambient", "Multiplier of the sky's ambient light in the clouds."},
      {"lightning.frequency_per_minute", &at<&S::lightning_per_minute>, 0, 600, R::Required, B::Lerp, "Weather",
       "Lightning / min", "Strikes per minute the weather spawns in its lightning volume."},
      {"rain.intensity", &at<&S::rain_intensity>, 0, 1, R::Required, B::Lerp, "Weather", "Rain",
       "Intensity of the rain drawn in the 2.5D sky (0..1)."},
      {"haze", &at<&S::haze>, 0, 1, R::Required, B::Lerp, "Weather", "Haze",
       "Scales the atmosphere's aerosol density and the height fog: x1 at 0.1, x4 at 0.4."},
      {"description", &at<&S::description>, 0, 0, R::Optional, B::Nearest, "Weather", "Description",
       "A note for people; the engine ignores it."},
  };
  return fields;
}

const WeatherField* find_weather_field(std::string_view key) {
  for (const WeatherField& f : weather_fields())
    if (f.key == key) return &f;
  return nullptr;
}

const WeatherObject* find_weather_object(std::string_view path) {
  static const std::map<std::string, WeatherObject, std::less<>> objects = [] {
    std::map<std::string, WeatherObject, std::less<>> out;
    for (const WeatherField& f : weather_fields()) {
      // Every prefix of the key is an object holding the next part.
      std::string parent;
      for (size_t start = 0;;) {
        const size_t dot = f.key.find('.', start);
        const std::string part(f.key.substr(start, dot == std::string_view::npos ? dot : dot - start));
        WeatherObject& o = out[parent];
        if (std::find(o.keys.begin(), o.keys.end(), part) == o.keys.end()) o.keys.push_back(part);
        if (f.rule != FieldRule::Optional) o.required.insert(part);
        if (dot == std::string_view::npos) break;
        parent = std::string(f.key.substr(0, dot));
        start = dot + 1;
      }
    }
    return out;
  }();
  auto it = objects.find(path);
  return it == objects.end() ? nullptr : &it->second;
}

Json field_json(const WeatherField& f, const WeatherState& s) {
  switch (f.type()) {
    case FieldType::Float:
      return member<float>(f, s);
    case FieldType::Int:
      return member<uint32_t>(f, s);
    case FieldType::Vec3: {
      const glm::vec3& v = member<glm::vec3>(f, s);
      return {v.x, v.y, v.z};
    }
    case FieldType::Text:
      return member<std::string>(f, s);
  }
  return nullptr;
}

void field_from_json(const WeatherField& f, const JsonView& v, WeatherState& s) {
  switch (f.type()) {
    case FieldType::Float:
      member<float>(f, s) = v.as_float_in(float(f.min), float(f.max));
      return;
    case FieldType::Int: {
      const uint32_t n = v.as<uint32_t>();
      if (n < f.min || n > f.max) {
        const std::string_view name = f.key.substr(f.key.rfind('.') + 1);  // npos + 1: the whole key
        v.fail(strf("expected %.0f..%.0f %.*s", f.min, f.max, int(name.size()), name.data()));
      }
      member<uint32_t>(f, s) = n;
      return;
    }
    case FieldType::Vec3: {
      glm::vec3 d = v.as_vec3();
      if (f.rule == FieldRule::Direction) {
        if (!(glm::length(d) > 1e-6f)) v.fail("expected a non-zero direction");
        d = glm::normalize(d);
      }
      member<glm::vec3>(f, s) = d;
      return;
    }
    case FieldType::Text:
      member<std::string>(f, s) = v.as<std::string>();
      return;
  }
}

void field_lerp(const WeatherField& f, const WeatherState& a, const WeatherState& b, float t, WeatherState& s) {
  if (f.type() == FieldType::Float) {
    const float x = member<float>(f, a), y = member<float>(f, b);
    member<float>(f, s) = x + (y - x) * t;
  } else if (f.type() == FieldType::Vec3) {
    member<glm::vec3>(f, s) = glm::mix(member<glm::vec3>(f, a), member<glm::vec3>(f, b), t);
  } else {
    fail("weather field %.*s: an integer or a string cannot be lerped", int(f.key.size()), f.key.data());
  }
}

}  // namespace cumulo::clouds::weather
