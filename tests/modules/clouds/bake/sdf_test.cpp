// Primitive SDFs against analytic values; soft-min and subtraction properties.
#include <gtest/gtest.h>

#include <random>

#include "modules/clouds/bake/sdf_primitives.h"

using namespace cumulo::clouds::bake;

TEST(SdfPrimitives, SphereIsExact) {
  EXPECT_FLOAT_EQ(sd_sphere({0, 0, 0}, 10), -10);
  EXPECT_FLOAT_EQ(sd_sphere({30, 0, 40}, 10), 40);
  EXPECT_NEAR(sd_sphere({0, 10, 0}, 10), 0, 1e-6);
}

TEST(SdfPrimitives, EllipsoidIsExactOnAxesAndSurface) {
  glm::vec3 r(100, 50, 25);
  // On the surface along each axis, and on a generic surface point.
  EXPECT_NEAR(sd_ellipsoid({100, 0, 0}, r), 0, 1e-4);
  EXPECT_NEAR(sd_ellipsoid({0, 50, 0}, r), 0, 1e-4);
  glm::vec3 s = glm::normalize(glm::vec3(1, 2, 3)) * r;
  EXPECT_NEAR(sd_ellipsoid(s, r), 0, 1e-3);
  // Along the smallest axis the bound is exact outside.
  EXPECT_NEAR(sd_ellipsoid({0, 0, 35}, r), 10, 1e-3);
  EXPECT_LT(sd_ellipsoid({0, 0, 0}, r), 0);
  // A sphere-shaped ellipsoid equals the sphere.
  EXPECT_NEAR(sd_ellipsoid({3, 4, 12}, glm::vec3(5)), sd_sphere({3, 4, 12}, 5), 1e-4);
}

TEST(SdfPrimitives, RoundBoxMatchesAnalytic) {
  glm::vec3 h(10, 20, 30);
  EXPECT_FLOAT_EQ(sd_round_box({15, 0, 0}, h, 0), 5);
  EXPECT_FLOAT_EQ(sd_round_box({0, 0, 0}, h, 0), -10);
  EXPECT_NEAR(sd_round_box({13, 24, 0}, h, 0), 5, 1e-5);  // edge region: distance to the edge
  // Rounded corner: the corner is cut back to a sphere of radius r centred r inside.
  float r = 4;
  glm::vec3 corner = h - r + glm::normalize(glm::vec3(1)) * (r + 2.0f);
  EXPECT_NEAR(sd_round_box(corner, h, r), 2.0f, 1e-4);
  EXPECT_FLOAT_EQ(sd_round_box({15, 0, 0}, h, r), 5);  // faces unchanged
}

TEST(SdfPrimitives, CapsuleMatchesAnalytic) {
  glm::vec3 a(0, 0, 0), b(0, 100, 0);
  EXPECT_FLOAT_EQ(sd_capsule({30, 50, 0}, a, b, 10), 20);
  EXPECT_FLOAT_EQ(sd_capsule({0, 130, 0}, a, b, 10), 20);
  EXPECT_FLOAT_EQ(sd_capsule({0, -5, 0}, a, b, 10), -5);
  EXPECT_FLOAT_EQ(sd_capsule({0, 50, 0}, a, b, 10), -10);
}

TEST(SoftMin, PropertiesOfTheBlend) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-200, 200), ku(1, 80);
  for (int i = 0; i < 10000; ++i) {
    float a = u(rng), b = u(rng), k = ku(rng), w;
    float s = smooth_union(a, b, k, &w);
    // Never above the hard min, at most k/4 below it; exactly the min once |a-b| >= k.
    EXPECT_LE(s, std::min(a, b) + 1e-4f);
    EXPECT_GE(s, std::min(a, b) - k * 0.25f - 1e-3f);
    if (std::abs(a - b) >= k) {
      EXPECT_NEAR(s, std::min(a, b), 1e-3f);
    }
    // Symmetric in its arguments; the weight goes to the smaller one.
    float w2;
    EXPECT_NEAR(s, smooth_union(b, a, k, &w2), 1e-3f);
    EXPECT_NEAR(w + w2, 1.0f, 1e-5f);
    if (b < a) {
      EXPECT_GE(w, 0.5f);
    }
    EXPECT_GE(w, 0.0f);
    EXPECT_LE(w, 1.0f);
  }
  float w;
  EXPECT_FLOAT_EQ(smooth_union(3, 5, 0, &w), 3);
  EXPECT_EQ(w, 0.0f);
  // Two equal values blend to v - k/4, weights half and half.
  EXPECT_NEAR(smooth_union(10, 10, 8, &w), 8, 1e-5);
  EXPECT_NEAR(w, 0.5f, 1e-6);
}

TEST(SoftMin, SubtractionCarves) {
  // Base sphere radius 100 at origin, cutter sphere radius 30 at (100, 0, 0).
  auto carve = [](glm::vec3 p, float k) {
    return smooth_subtract(sd_sphere(p, 100), sd_sphere(p - glm::vec3(100, 0, 0), 30), k);
  };
  EXPECT_GT(carve({90, 0, 0}, 0), 0);                             // inside the cutter: empty now
  EXPECT_FLOAT_EQ(carve({-50, 0, 0}, 0), sd_sphere({-50, 0, 0}, 100));  // far from the cutter: unchanged
  EXPECT_FLOAT_EQ(carve({90, 0, 0}, 0), 20);                      // max(d, -cutter)
  for (float k : {0.0f, 10.0f, 40.0f}) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-150, 150);
    for (int i = 0; i < 2000; ++i) {
      glm::vec3 p(u(rng), u(rng), u(rng));
      float a = sd_sphere(p, 100), b = sd_sphere(p - glm::vec3(100, 0, 0), 30);
      float s = smooth_subtract(a, b, k);
      EXPECT_GE(s, std::max(a, -b) - 1e-3f);  // only ever removes
      EXPECT_LE(s, std::max(a, -b) + k * 0.25f + 1e-3f);
    }
  }
  float w;
  EXPECT_FLOAT_EQ(smooth_intersect(-5, 3, 0, &w), 3);
  EXPECT_EQ(w, 1.0f);
}
