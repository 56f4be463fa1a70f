#pragma once
// Signed distance primitives and blend operators for cloudscape recipes.
//
// Index:  sd_sphere  sd_ellipsoid  sd_round_box  sd_capsule   |  smooth_union  smooth_subtract  smooth_intersect
//
// Distances are in metres, negative inside. Formulas follow Inigo Quilez's "distance functions"
// articles, which the 2023 talk points to for SDF primitives; the smooth operators are the
// polynomial soft-min that Media Molecule's Dreams edit lists blend with (seed 004: "soft min ...
// blend radius"). Each blend also returns the weight of the new edit, so per-voxel attributes
// (detail type, density scale) blend with the same weights as the distance.
#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace cumulo::clouds::bake {

inline float sd_sphere(glm::vec3 p, float r) { return glm::length(p) - r; }

// IQ's ellipsoid bound (k0 * (k0 - 1) / k1): exact on the surface, a good estimate near it.
inline float sd_ellipsoid(glm::vec3 p, glm::vec3 r) {
  float k0 = glm::length(p / r);
  float k1 = glm::length(p / (r * r));
  if (k1 <= 0.0f) return -std::min(r.x, std::min(r.y, r.z));
  return k0 * (k0 - 1.0f) / k1;
}

// Box of half extents `half` whose edges are rounded by `radius` (radius <= min(half)).
inline float sd_round_box(glm::vec3 p, glm::vec3 half, float radius) {
  glm::vec3 q = glm::abs(p) - half + radius;
  return glm::length(glm::max(q, 0.0f)) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f) - radius;
}

// Segment a-b swept by a sphere of radius r.
inline float sd_capsule(glm::vec3 p, glm::vec3 a, glm::vec3 b, float r) {
  glm::vec3 pa = p - a, ba = b - a;
  float denom = glm::dot(ba, ba);
  float h = denom > 0.0f ? std::clamp(glm::dot(pa, ba) / denom, 0.0f, 1.0f) : 0.0f;
  return glm::length(pa - ba * h) - r;
}

// Polynomial smooth minimum of the accumulated field `a` and a new edit `b` with blend radius k
// (k = 0: hard min). *w_new receives the new edit's weight in [0, 1] (1 where b wins outright).
inline float smooth_union(float a, float b, float k, float* w_new) {
  if (k <= 0.0f) {
    *w_new = b < a ? 1.0f : 0.0f;
    return std::min(a, b);
  }
  float h = std::clamp(0.5f + 0.5f * (a - b) / k, 0.0f, 1.0f);  // weight of b
  *w_new = h;
  return a + (b - a) * h - k * h * (1.0f - h);
}

// Smooth max(a, -b): carves the cutter b out of a (caves, tunnels).
inline float smooth_subtract(float a, float b, float k) {
  if (k <= 0.0f) return std::max(a, -b);
  float h = std::clamp(0.5f - 0.5f * (a + b) / k, 0.0f, 1.0f);  // weight of -b
  return a + (-b - a) * h + k * h * (1.0f - h);
}

// Smooth max(a, b): keeps only what both cover.
inline float smooth_intersect(float a, float b, float k, float* w_new) {
  if (k <= 0.0f) {
    *w_new = b > a ? 1.0f : 0.0f;
    return std::max(a, b);
  }
  float h = std::clamp(0.5f - 0.5f * (b - a) / k, 0.0f, 1.0f);  // weight of a
  *w_new = 1.0f - h;
  return b + (a - b) * h + k * h * (1.0f - h);
}

}  // namespace cumulo::clouds::bake
