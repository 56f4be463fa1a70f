#include "modules/clouds/volume/distance.h"

#include <cmath>
#include <limits>

#include "engine/core/parallel.h"

namespace cumulo::clouds {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// 1D squared distance transform of f (length n) into d, FH 2012 algorithm 1. v, z: scratch.
// The envelope is computed in double: q^2 reaches 16M at 4096 voxels, beyond float's exact range.
void dt1d(const float* f, float* d, uint32_t n, std::vector<int>& v, std::vector<double>& z) {
  v.resize(n);
  z.resize(n + 1);
  int k = -1;
  for (uint32_t q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;  // parabolas at infinity never form the envelope
    const double fq = double(f[q]) + double(q) * q;
    while (k >= 0) {
      const int p = v[k];
      const double s = (fq - (double(f[p]) + double(p) * p)) / (2.0 * q - 2.0 * p);
      if (s <= z[k]) {
        --k;
        continue;
      }
      v[++k] = int(q);
      z[k] = s;
      z[k + 1] = kInf;
      break;
    }
    if (k < 0) {
      k = 0;
      v[0] = int(q);
      z[0] = -kInf;
      z[1] = kInf;
    }
  }
  if (k < 0) {
    for (uint32_t q = 0; q < n; ++q) d[q] = kInf;
    return;
  }
  int j = 0;
  for (uint32_t q = 0; q < n; ++q) {
    while (z[j + 1] < double(q)) ++j;
    const double dq = double(q) - v[j];
    d[q] = static_cast<float>(dq * dq + f[v[j]]);
  }
}

// Runs dt1d along one axis of the grid in place.
void transform_axis(std::vector<float>& g, glm::uvec3 s, int axis) {
  const uint32_t n = s[axis];
  const size_t stride = axis == 0 ? 1 : axis == 1 ? size_t(s.x) : size_t(s.x) * s.y;
  const uint32_t a = axis == 0 ? s.y : s.x;  // the two other axes enumerate the lines
  const uint32_t b = axis == 2 ? s.y : s.z;
  parallel_for(size_t(a) * b, [&](size_t begin, size_t end) {
    std::vector<float> f(n), d(n);
    std::vector<double> zs;
    std::vector<int> vs;
    for (size_t line = begin; line < end; ++line) {
      const size_t i = line % a, j = line / a;
      size_t base;
      if (axis == 0) base = (j * s.y + i) * s.x;           // i = y, j = z
      else if (axis == 1) base = j * size_t(s.x) * s.y + i;  // i = x, j = z
      else base = j * s.x + i;                              // i = x, j = y
      for (uint32_t q = 0; q < n; ++q) f[q] = g[base + q * stride];
      dt1d(f.data(), d.data(), n, vs, zs);
      for (uint32_t q = 0; q < n; ++q) g[base + q * stride] = d[q];
    }
  }, 8);
}

}  // namespace

std::vector<float> squared_distance_to_mask(const std::vector<uint8_t>& mask, glm::uvec3 size) {
  std::vector<float> g(mask.size());
  for (size_t i = 0; i < mask.size(); ++i) g[i] = mask[i] ? 0.0f : kInf;
  for (int axis = 0; axis < 3; ++axis) transform_axis(g, size, axis);
  return g;
}

std::vector<float> signed_distance_from_mask(const std::vector<uint8_t>& inside, glm::uvec3 size, float voxel_size) {
  std::vector<uint8_t> outside(inside.size());
  for (size_t i = 0; i < inside.size(); ++i) outside[i] = inside[i] ? 0 : 1;
  std::vector<float> to_inside = squared_distance_to_mask(inside, size);
  std::vector<float> to_outside = squared_distance_to_mask(outside, size);
  std::vector<float> sdf(inside.size());
  const float half = 0.5f * voxel_size;
  for (size_t i = 0; i < inside.size(); ++i)
    sdf[i] = inside[i] ? -(std::sqrt(to_outside[i]) * voxel_size - half) : std::sqrt(to_inside[i]) * voxel_size - half;
  return sdf;
}

}  // namespace cumulo::clouds
