#pragma once
// The sun from the time of day: a simple astronomical model (solar declination from the day of the year,
// hour angle from local solar time), good to a degree or so, which is all lighting needs.
//
//   TimeOfDay tod;  tod.hours = 7.0f;
//   glm::vec3 to_sun = sun_direction(tod);          // world space, unit, pointing toward the sun
//   SunPosition p = sun_position(tod);              // elevation / azimuth in degrees, same direction
//
// World axes: +X east, -Z north, +Y up, rotated about +Y by TimeOfDay::north_deg.
#include <glm/glm.hpp>

#include "engine/ecs/world.h"
#include "engine/scene/components.h"

namespace cumulo::scene {

struct SunPosition {
  float elevation_deg = 0.0f;  // above the horizon; negative at night
  float azimuth_deg = 0.0f;    // compass bearing, clockwise from north (90 = east), in [0, 360)
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // world-space unit vector toward the sun
};

// Declination in degrees (Cooper's approximation: -23.44 * cos(360/365 * (day + 10))).
float solar_declination_deg(int day_of_year);
SunPosition sun_position(const TimeOfDay& tod);
glm::vec3 sun_direction(const TimeOfDay& tod);
// Inverse of the compass convention: world-space unit vector for an elevation and a compass azimuth.
glm::vec3 direction_from_elevation_azimuth(float elevation_deg, float azimuth_deg, float north_deg = 0.0f);

// Fraction of sunlight left after the atmosphere, per RGB channel, for a sun at `elevation_deg`: Beer-Lambert
// over the Kasten-Young air mass with sea-level optical depths (0.10, 0.18, 0.38) for (R, G, B) (Rayleigh
// plus a little aerosol), faded to zero as the sun sinks 2 degrees below the horizon. It reddens the
// low sun; the cloud module's atmosphere replaces it with a real sky model.
glm::vec3 sun_transmittance(float elevation_deg);

// The renderer's directional light: the one sun description every pass and module uses.
struct SunLight {
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // toward the sun, world space, unit
  glm::vec3 radiance{1.0f};               // Sun::color * Sun::illuminance * sun_transmittance(elevation)
  glm::vec3 top_of_atmosphere{1.0f};      // Sun::color * Sun::illuminance (before the atmosphere)
  float elevation_deg = 90.0f;
  float azimuth_deg = 0.0f;
};
SunLight sun_light(const TimeOfDay& tod, const Sun& sun);

// The one rule for which TimeOfDay and Sun count (the day-cycle system, `--time-of-day`, extraction and
// every module use it, nothing else looks): the world resource TimeOfDay (with the Sun resource) when the
// world has one; else the first entity, in slot order, with a TimeOfDay (with that entity's Sun). Null
// members: none in the world (defaults apply).
struct SunSource {
  TimeOfDay* time = nullptr;
  const Sun* sun = nullptr;
};
SunSource find_sun(ecs::World& world);
struct ConstSunSource {
  const TimeOfDay* time = nullptr;
  const Sun* sun = nullptr;
};
ConstSunSource find_sun(const ecs::World& world);
// sun_light() of find_sun(world), defaults where it found nothing.
SunLight find_sun_light(const ecs::World& world);
// The TimeOfDay that counts, created as a world resource when the world has none: where `--time-of-day`
// writes its hours.
TimeOfDay& time_of_day_to_set(ecs::World& world);

// Advances hours by `seconds` of simulation at tod.hours_per_second, wrapping into [0, 24).
void advance_time_of_day(TimeOfDay& tod, double seconds);

}  // namespace cumulo::scene
