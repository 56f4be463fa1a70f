#include "modules/clouds/bake/field.h"

#include <algorithm>
#include <cmath>

#include "engine/core/parallel.h"
#include "engine/core/progress.h"
#include "modules/clouds/volume/distance.h"

namespace cumulo::clouds::bake {

std::vector<float> build_field(const std::vector<float>& composed, const BakeGrid& grid, FieldStats* stats,
                               Progress* progress) {
  const glm::uvec3 d = grid.dims;
  const size_t n = grid.count();
  std::vector<uint8_t> inside(n), outside(n);
  uint64_t n_inside = 0;
  for (size_t i = 0; i < n; ++i) {
    inside[i] = composed[i] < 0.0f;
    outside[i] = !inside[i];
    n_inside += inside[i];
  }
  std::vector<float> to_inside = squared_distance_to_mask(inside, d, grid.spacing);
  if (progress) progress->add(1.0);
  std::vector<float> to_outside = squared_distance_to_mask(outside, d, grid.spacing);
  if (progress) progress->add(1.0);
  const float half = 0.5f * std::min(grid.spacing.x, std::min(grid.spacing.y, grid.spacing.z));

  std::vector<float> field(n);
  std::vector<uint64_t> surface_rows(size_t(d.y) * d.z, 0);
  parallel_for(size_t(d.y) * d.z, [&](size_t b, size_t e) {
    for (size_t row = b; row < e; ++row) {
      uint32_t y = row % d.y, z = row / d.y;
      for (uint32_t x = 0; x < d.x; ++x) {
        size_t i = grid.index(x, y, z);
        float edt = inside[i] ? -(std::sqrt(to_outside[i]) - half) : std::sqrt(to_inside[i]) - half;
        // Surface voxel: a 6-neighbour on the other side.
        bool surface = false;
        glm::vec3 grad(0.0f);
        const uint32_t c[3] = {x, y, z};
        for (int a = 0; a < 3; ++a) {
          uint32_t lo = c[a] > 0 ? c[a] - 1 : c[a], hi = c[a] + 1 < d[a] ? c[a] + 1 : c[a];
          uint32_t pl[3] = {x, y, z}, ph[3] = {x, y, z};
          pl[a] = lo, ph[a] = hi;
          size_t il = grid.index(pl[0], pl[1], pl[2]), ih = grid.index(ph[0], ph[1], ph[2]);
          surface |= inside[il] != inside[i] || inside[ih] != inside[i];
          if (hi > lo) grad[a] = (composed[ih] - composed[il]) / (float(hi - lo) * grid.spacing[a]);
        }
        float value = edt;
        if (surface) {
          ++surface_rows[row];
          float g = std::clamp(glm::length(grad), 0.25f, 4.0f);
          float analytic = composed[i] / g;
          value = inside[i] ? std::max(analytic, edt) : std::min(analytic, edt);
        }
        field[i] = std::clamp(value, kFieldMin, kFieldMax);
      }
    }
  });
  if (progress) progress->add(1.0);
  if (stats) {
    stats->inside_voxels = n_inside;
    stats->surface_voxels = 0;
    for (uint64_t s : surface_rows) stats->surface_voxels += s;
  }
  return field;
}

float profile_from_field(float sdf_m, const ProfileParams& p) {
  float t = std::clamp(-sdf_m / p.depth, 0.0f, 1.0f);
  return p.exponent == 1.0f ? t : std::pow(t, p.exponent);
}

}  // namespace cumulo::clouds::bake
