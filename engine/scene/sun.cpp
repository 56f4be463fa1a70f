#include "engine/scene/sun.h"

#include <cmath>

namespace cumulo::scene {

namespace {
constexpr float kPi = 3.14159265358979f;
float rad(float deg) { return deg * (kPi / 180.0f); }
float deg(float r) { return r * (180.0f / kPi); }
}  // namespace

float solar_declination_deg(int day_of_year) {
  return -23.44f * std::cos(rad(360.0f / 365.0f * float(day_of_year + 10)));
}

glm::vec3 direction_from_elevation_azimuth(float elevation_deg, float azimuth_deg, float north_deg) {
  float el = rad(elevation_deg);
  float az = rad(azimuth_deg + north_deg);
  // Compass bearing az (clockwise from north) -> east * sin(az) + north * cos(az); east = +X, north = -Z.
  return glm::vec3(std::cos(el) * std::sin(az), std::sin(el), -std::cos(el) * std::cos(az));
}

SunPosition sun_position(const TimeOfDay& tod) {
  float phi = rad(tod.latitude_deg);
  float delta = rad(solar_declination_deg(tod.day_of_year));
  float h = rad(15.0f * (tod.hours - 12.0f));  // hour angle: 15 degrees per hour from solar noon
  // The sun's direction in the local east/north/up frame (a unit vector by construction).
  float east = -std::cos(delta) * std::sin(h);
  float north = std::cos(phi) * std::sin(delta) - std::sin(phi) * std::cos(delta) * std::cos(h);
  float up = std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(h);
  SunPosition p;
  p.elevation_deg = deg(std::asin(glm::clamp(up, -1.0f, 1.0f)));
  float az = deg(std::atan2(east, north));
  p.azimuth_deg = az < 0.0f ? az + 360.0f : az;
  p.direction = glm::normalize(direction_from_elevation_azimuth(p.elevation_deg, p.azimuth_deg, tod.north_deg));
  return p;
}

glm::vec3 sun_direction(const TimeOfDay& tod) { return sun_position(tod).direction; }

glm::vec3 sun_transmittance(float elevation_deg) {
  if (elevation_deg <= -2.0f) return glm::vec3(0.0f);
  float e = std::max(elevation_deg, 0.0f);
  // Kasten & Young (1989) relative air mass; 38 at the horizon.
  float air_mass = 1.0f / (std::sin(rad(e)) + 0.50572f * std::pow(e + 6.07995f, -1.6364f));
  glm::vec3 tau(0.10f, 0.18f, 0.38f);
  glm::vec3 t = glm::exp(-tau * air_mass);
  float fade = glm::clamp((elevation_deg + 2.0f) / 2.0f, 0.0f, 1.0f);  // twilight below the horizon
  return t * fade;
}

SunLight sun_light(const TimeOfDay& tod, const Sun& sun) {
  SunPosition p = sun_position(tod);
  SunLight l;
  l.direction = p.direction;
  l.elevation_deg = p.elevation_deg;
  l.azimuth_deg = p.azimuth_deg;
  l.top_of_atmosphere = sun.color * sun.illuminance;
  l.radiance = l.top_of_atmosphere * sun_transmittance(p.elevation_deg);
  return l;
}

namespace {

template <class World, class Source>
Source find_sun_in(World& world) {
  Source s;
  if (auto* tod = world.template try_resource<TimeOfDay>()) {
    s.time = tod;
    s.sun = world.template try_resource<Sun>();
    return s;
  }
  ecs::Entity found = ecs::Entity::null();
  world.each_entity([&](ecs::Entity e) {
    if (found.is_null() && world.template has<TimeOfDay>(e)) found = e;
  });
  if (found.is_null()) return s;
  s.time = &world.template get<TimeOfDay>(found);
  s.sun = world.template try_get<Sun>(found);
  return s;
}

}  // namespace

SunSource find_sun(ecs::World& world) { return find_sun_in<ecs::World, SunSource>(world); }
ConstSunSource find_sun(const ecs::World& world) { return find_sun_in<const ecs::World, ConstSunSource>(world); }

SunLight find_sun_light(const ecs::World& world) {
  ConstSunSource s = find_sun(world);
  return sun_light(s.time ? *s.time : TimeOfDay{}, s.sun ? *s.sun : Sun{});
}

TimeOfDay& time_of_day_to_set(ecs::World& world) {
  if (TimeOfDay* t = find_sun(world).time) return *t;
  return world.set_resource<TimeOfDay>();
}

void advance_time_of_day(TimeOfDay& tod, double seconds) {
  double h = double(tod.hours) + double(tod.hours_per_second) * seconds;
  h = std::fmod(h, 24.0);
  if (h < 0.0) h += 24.0;
  tod.hours = float(h);
  if (tod.hours >= 24.0f) tod.hours = 0.0f;  // float rounding of 23.9999999
}

}  // namespace cumulo::scene
