// The sun from the time of day: known positions (equinox, solstice), compass conventions, day cycle.
#include <gtest/gtest.h>

#include "engine/scene/sun.h"

using namespace cumulo;
using namespace cumulo::scene;

namespace {
bool near(const glm::vec3& a, const glm::vec3& b, float eps = 2e-2f) { return glm::length(a - b) < eps; }

// Day 81 (22 March) is within a fraction of a degree of the equinox in the approximation.
TimeOfDay at(float hours, float latitude, int day = 81) {
  TimeOfDay t;
  t.hours = hours;
  t.latitude_deg = latitude;
  t.day_of_year = day;
  return t;
}
}  // namespace

TEST(Sun, DeclinationAtSolsticesAndEquinox) {
  EXPECT_NEAR(solar_declination_deg(172), 23.44f, 0.1f);   // 21 June
  EXPECT_NEAR(solar_declination_deg(355), -23.44f, 0.1f);  // 21 December
  EXPECT_NEAR(solar_declination_deg(81), 0.0f, 0.5f);
}

TEST(Sun, EquatorAtEquinoxRisesEastPassesOverheadSetsWest) {
  EXPECT_TRUE(near(sun_direction(at(12, 0)), {0, 1, 0}));
  EXPECT_TRUE(near(sun_direction(at(6, 0)), {1, 0, 0}));    // east is +X
  EXPECT_TRUE(near(sun_direction(at(18, 0)), {-1, 0, 0}));  // west is -X
  EXPECT_LT(sun_position(at(0, 0)).elevation_deg, -80.0f);  // midnight: below the horizon
}

TEST(Sun, MidLatitudeNoonIsDueSouthAtNinetyMinusLatitude) {
  SunPosition p = sun_position(at(12, 45));
  EXPECT_NEAR(p.elevation_deg, 45.0f, 0.5f);
  EXPECT_NEAR(p.azimuth_deg, 180.0f, 0.5f);
  EXPECT_TRUE(near(p.direction, {0, 0.7071f, 0.7071f}));  // south is +Z
  // Southern hemisphere: the noon sun is due north (-Z).
  SunPosition s = sun_position(at(12, -30));
  EXPECT_NEAR(s.azimuth_deg, 0.0f, 0.5f);
  EXPECT_LT(s.direction.z, 0.0f);
}

TEST(Sun, SummerSolsticeNoonInLosAngeles) {
  // 90 - 34.05 + 23.44 = 79.4 degrees.
  EXPECT_NEAR(sun_position(at(12, 34.05f, 172)).elevation_deg, 79.4f, 0.3f);
  // Afternoon: the sun is in the west half of the sky, and lower.
  SunPosition p = sun_position(at(16.5f, 34.05f, 240));
  EXPECT_GT(p.azimuth_deg, 180.0f);
  EXPECT_LT(p.direction.x, 0.0f);
  EXPECT_GT(p.elevation_deg, 10.0f);
  EXPECT_LT(p.elevation_deg, 60.0f);
  EXPECT_NEAR(glm::length(p.direction), 1.0f, 1e-5f);
}

TEST(Sun, NorthRotationTurnsTheCompass) {
  TimeOfDay t = at(6, 0);
  t.north_deg = 90.0f;  // true north along +X, so east (the rising sun) is along +Z
  glm::vec3 d = sun_direction(t);
  EXPECT_TRUE(near(d, direction_from_elevation_azimuth(0.0f, 180.0f)));
  EXPECT_TRUE(near(direction_from_elevation_azimuth(0, 90), {1, 0, 0}, 1e-5f));
  EXPECT_TRUE(near(direction_from_elevation_azimuth(90, 0), {0, 1, 0}, 1e-5f));
}

TEST(Sun, TransmittanceReddensTheLowSunAndVanishesAtNight) {
  glm::vec3 high = sun_transmittance(80.0f), low = sun_transmittance(3.0f);
  EXPECT_GT(high.b, 0.6f);
  EXPECT_GT(low.r, low.g);
  EXPECT_GT(low.g, low.b);
  EXPECT_LT(low.b, high.b);
  EXPECT_EQ(sun_transmittance(-5.0f), glm::vec3(0.0f));
}

TEST(Sun, DayCycleAdvancesAndWraps) {
  TimeOfDay t;
  t.hours = 23.0f;
  t.hours_per_second = 0.5f;
  advance_time_of_day(t, 4.0);  // +2 h
  EXPECT_NEAR(t.hours, 1.0f, 1e-5f);
  t.hours_per_second = -1.0f;
  advance_time_of_day(t, 3.0);
  EXPECT_NEAR(t.hours, 22.0f, 1e-5f);
  t.hours_per_second = 0.0f;
  advance_time_of_day(t, 1000.0);
  EXPECT_NEAR(t.hours, 22.0f, 1e-5f);
}

TEST(Sun, FindSunLightInAWorld) {
  ecs::World world;
  SunLight none = find_sun_light(world);  // defaults when the level has no TimeOfDay
  EXPECT_NEAR(glm::length(none.direction), 1.0f, 1e-5f);
  ecs::Entity e = world.create();
  world.emplace<TimeOfDay>(e, at(12, 0));
  world.emplace<Sun>(e, Sun{glm::vec3(1, 0.5f, 0.25f), 2.0f});
  SunLight l = find_sun_light(world);
  EXPECT_TRUE(near(l.direction, {0, 1, 0}));
  EXPECT_NEAR(l.radiance.r, 2.0f * sun_transmittance(90.0f).r, 1e-3f);
  EXPECT_NEAR(l.radiance.g, 1.0f * sun_transmittance(90.0f).g, 1e-3f);
  EXPECT_EQ(find_sun(world).time, &world.get<TimeOfDay>(e));
}

TEST(Sun, TheWorldResourceCountsOverEntities) {
  ecs::World world;
  ecs::Entity e = world.create();
  world.emplace<TimeOfDay>(e, at(12, 0));
  ecs::Entity second = world.create();
  world.emplace<TimeOfDay>(second, at(6, 0));
  EXPECT_EQ(find_sun(world).time, &world.get<TimeOfDay>(e));  // the first entity, not the second
  // --time-of-day writes the one that counts; no resource is made while an entity has one.
  time_of_day_to_set(world).hours = 9.0f;
  EXPECT_FLOAT_EQ(world.get<TimeOfDay>(e).hours, 9.0f);
  EXPECT_FLOAT_EQ(world.get<TimeOfDay>(second).hours, 6.0f);
  EXPECT_EQ(world.try_resource<TimeOfDay>(), nullptr);
  // A resource wins over every entity, with the Sun resource beside it.
  world.set_resource<TimeOfDay>(at(18, 0));
  world.set_resource<Sun>(Sun{glm::vec3(0.5f), 1.0f});
  EXPECT_EQ(find_sun(world).time, world.try_resource<TimeOfDay>());
  EXPECT_NEAR(find_sun_light(world).radiance.r, 0.5f * sun_transmittance(find_sun_light(world).elevation_deg).r, 1e-4f);
  ecs::World empty;
  EXPECT_EQ(find_sun(empty).time, nullptr);
  time_of_day_to_set(empty).hours = 3.0f;
  ASSERT_NE(empty.try_resource<TimeOfDay>(), nullptr);
  EXPECT_FLOAT_EQ(empty.try_resource<TimeOfDay>()->hours, 3.0f);
}
