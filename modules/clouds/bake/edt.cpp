#include "modules/clouds/bake/edt.h"

#include <algorithm>
#include <limits>

#include "engine/core/parallel.h"

namespace cumulo::clouds::bake {

void edt_1d(const float* f, int n, float spacing, float* d, int* v, double* z) {
  // Lower envelope of the parabolas rooted at every finite sample q: y = (x - q)^2 s^2 + f[q].
  const double s2 = static_cast<double>(spacing) * spacing;
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] >= kEdtInfinity) continue;
    double fq = f[q] + s2 * q * q;
    while (k >= 0) {
      // Where parabola q overtakes the envelope's last one (in grid units).
      int r = v[k];
      double x = (fq - (f[r] + s2 * r * r)) / (2.0 * s2 * (q - r));
      if (x <= z[k]) {
        --k;
      } else {
        ++k;
        v[k] = q;
        z[k] = x;
        z[k + 1] = std::numeric_limits<double>::infinity();
        break;
      }
    }
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -std::numeric_limits<double>::infinity();
      z[1] = std::numeric_limits<double>::infinity();
    }
  }
  if (k < 0) {
    std::fill(d, d + n, kEdtInfinity);
    return;
  }
  int j = 0;
  for (int p = 0; p < n; ++p) {
    while (z[j + 1] < p) ++j;
    double dx = p - v[j];
    double val = s2 * dx * dx + f[v[j]];
    d[p] = val >= kEdtInfinity ? kEdtInfinity : static_cast<float>(val);
  }
}

std::vector<float> squared_edt(const std::vector<uint8_t>& sites, glm::uvec3 dims, glm::vec3 spacing) {
  const size_t nx = dims.x, ny = dims.y, nz = dims.z;
  std::vector<float> g(nx * ny * nz);
  for (size_t i = 0; i < g.size(); ++i) g[i] = sites[i] ? 0.0f : kEdtInfinity;

  // One pass along `axis` over every line of the volume; lines are independent.
  auto pass = [&](int axis) {
    const size_t n = dims[axis];
    const size_t stride = axis == 0 ? 1 : axis == 1 ? nx : nx * ny;
    const size_t lines = g.size() / n;
    parallel_for(
        lines,
        [&](size_t b, size_t e) {
          std::vector<float> in(n), out(n);
          std::vector<int> v(n);
          std::vector<double> z(n + 1);
          for (size_t line = b; line < e; ++line) {
            // Index of the line's first voxel: decompose `line` over the two other axes.
            size_t base;
            if (axis == 0) {
              base = line * nx;
            } else if (axis == 1) {
              size_t x = line % nx, zz = line / nx;
              base = x + zz * nx * ny;
            } else {
              base = line;  // (x, y) plane index
            }
            for (size_t i = 0; i < n; ++i) in[i] = g[base + i * stride];
            edt_1d(in.data(), static_cast<int>(n), spacing[axis], out.data(), v.data(), z.data());
            for (size_t i = 0; i < n; ++i) g[base + i * stride] = out[i];
          }
        },
        16);
  };
  pass(0);
  pass(1);
  pass(2);
  return g;
}

}  // namespace cumulo::clouds::bake
