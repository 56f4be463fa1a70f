#include "modules/clouds/soak/soak_path.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::clouds::soak {
namespace {

constexpr int kSamples = 64;  // per segment, for the arc length

}  // namespace

SoakPath::SoakPath(std::vector<glm::vec3> points) {
  // Consecutive duplicates would make a zero-length segment (no direction to look along).
  for (const glm::vec3& p : points)
    if (points_.empty() || glm::distance(points_.back(), p) > 1.0f) points_.push_back(p);
  while (points_.size() > 1 && glm::distance(points_.back(), points_.front()) <= 1.0f) points_.pop_back();
  if (points_.size() < 2) fail("soak: the camera path needs two distinct points (the level's cameras and weather zones)");
  const size_t n = points_.size();
  arc_.assign(n * kSamples + 1, 0.0f);
  glm::vec3 prev = spline(0, 0.0f);
  for (size_t i = 1; i <= n * kSamples; ++i) {
    const glm::vec3 p = spline((i - 1) / kSamples, float((i - 1) % kSamples + 1) / kSamples);
    arc_[i] = arc_[i - 1] + glm::distance(prev, p);
    prev = p;
  }
  length_ = arc_.back();
}

glm::vec3 SoakPath::spline(size_t segment, float t) const {
  // Centripetal-free uniform Catmull-Rom over the closed loop: passes through every point.
  const size_t n = points_.size();
  const glm::vec3& p0 = points_[(segment + n - 1) % n];
  const glm::vec3& p1 = points_[segment % n];
  const glm::vec3& p2 = points_[(segment + 1) % n];
  const glm::vec3& p3 = points_[(segment + 2) % n];
  const float t2 = t * t, t3 = t2 * t;
  return 0.5f * (2.0f * p1 + (p2 - p0) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * t3);
}

glm::vec3 SoakPath::position(double u) const {
  u -= std::floor(u);
  const float s = float(u) * length_;
  const size_t i = size_t(std::upper_bound(arc_.begin(), arc_.end(), s) - arc_.begin());
  const size_t hi = std::clamp<size_t>(i, 1, arc_.size() - 1), lo = hi - 1;
  const float span = arc_[hi] - arc_[lo];
  const float f = span > 0.0f ? (s - arc_[lo]) / span : 0.0f;
  const float sample = float(lo) + f;  // in samples along the loop
  const size_t segment = std::min(size_t(sample) / kSamples, points_.size() - 1);
  return spline(segment, (sample - float(segment * kSamples)) / kSamples);
}

scene::Transform SoakPath::transform(double u) const {
  const glm::vec3 p = position(u);
  glm::vec3 ahead = position(u + 0.02);
  if (glm::distance(ahead, p) < 1e-3f) ahead = p + glm::vec3(0.0f, 0.0f, -1.0f);
  return scene::Transform::look_at(p, ahead);
}

SoakPath make_soak_path(const ecs::World& world) {
  std::vector<glm::vec3> loop;
  world.each_entity([&](ecs::Entity e) {
    if (world.has<scene::Camera>(e) && world.has<scene::Transform>(e)) loop.push_back(world.get<scene::Transform>(e).position);
  });
  std::vector<glm::vec3> zones;
  world.each_entity([&](ecs::Entity e) {
    if (const auto* z = world.try_get<weather::WeatherZone>(e))
      zones.push_back(z->sphere ? z->center : 0.5f * (z->min + z->max));
  });
  // Each zone's centre where it adds the least length (the loop stays a tour of the cameras).
  for (const glm::vec3& z : zones) {
    if (loop.empty()) {
      loop.push_back(z);
      continue;
    }
    size_t best = 0;
    float best_cost = INFINITY;
    for (size_t i = 0; i < loop.size(); ++i) {
      const glm::vec3& a = loop[i];
      const glm::vec3& b = loop[(i + 1) % loop.size()];
      const float cost = glm::distance(a, z) + glm::distance(z, b) - glm::distance(a, b);
      if (cost < best_cost) best_cost = cost, best = i;
    }
    loop.insert(loop.begin() + std::ptrdiff_t(best + 1), z);
  }
  return SoakPath(std::move(loop));
}

}  // namespace cumulo::clouds::soak
