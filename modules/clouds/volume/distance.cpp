#include "modules/clouds/volume/distance.h"

#include <algorithm>
#include <cmath>

#include "engine/core/parallel.h"

namespace cumulo::clouds {

void squared_distance_1d(const float* f, uint32_t n, float spacing, float* d, int* v, double* z) {
  // Lower envelope of the parabolas rooted at every finite sample q: y = (x - q)^2 s^2 + f[q] (FH 2012
  // algorithm 1). Computed in double: q^2 reaches 16M at 4096 voxels, beyond float's exact range.
  const double s2 = static_cast<double>(spacing) * spacing;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int k = -1;
  for (uint32_t qu = 0; qu < n; ++qu) {
    const int q = static_cast<int>(qu);
    if (f[q] == kNoSiteDistance2) continue;  // parabolas at infinity never form the envelope
    const double fq = f[q] + s2 * q * q;
    while (k >= 0) {
      // Where parabola q overtakes the envelope's last one (in grid units).
      const int r = v[k];
      const double x = (fq - (f[r] + s2 * r * r)) / (2.0 * s2 * (q - r));
      if (x <= z[k]) {
        --k;
      } else {
        ++k;
        v[k] = q;
        z[k] = x;
        z[k + 1] = kInf;
        break;
      }
    }
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
    }
  }
  if (k < 0) {
    std::fill(d, d + n, kNoSiteDistance2);
    return;
  }
  int j = 0;
  for (uint32_t p = 0; p < n; ++p) {
    while (z[j + 1] < p) ++j;
    const double dx = double(p) - v[j];
    d[p] = static_cast<float>(s2 * dx * dx + f[v[j]]);
  }
}

std::vector<float> squared_distance_to_mask(const std::vector<uint8_t>& mask, glm::uvec3 size, glm::vec3 spacing) {
  const size_t nx = size.x, ny = size.y;
  std::vector<float> g(mask.size());
  for (size_t i = 0; i < mask.size(); ++i) g[i] = mask[i] ? 0.0f : kNoSiteDistance2;
  if (g.empty()) return g;

  // One pass along `axis` over every line of the volume; lines are independent.
  auto pass = [&](int axis) {
    const uint32_t n = size[axis];
    const size_t stride = axis == 0 ? 1 : axis == 1 ? nx : nx * ny;
    parallel_for(
        g.size() / n,
        [&](size_t b, size_t e) {
          std::vector<float> in(n), out(n);
          std::vector<int> v(n);
          std::vector<double> z(n + 1);
          for (size_t line = b; line < e; ++line) {
            // Index of the line's first voxel: decompose `line` over the two other axes.
            size_t base;
            if (axis == 0) base = line * nx;                                // line = y + z * ny
            else if (axis == 1) base = line % nx + (line / nx) * nx * ny;  // line = x + z * nx
            else base = line;                                               // line = x + y * nx
            for (uint32_t i = 0; i < n; ++i) in[i] = g[base + i * stride];
            squared_distance_1d(in.data(), n, spacing[axis], out.data(), v.data(), z.data());
            for (uint32_t i = 0; i < n; ++i) g[base + i * stride] = out[i];
          }
        },
        16);
  };
  pass(0);
  pass(1);
  pass(2);
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
