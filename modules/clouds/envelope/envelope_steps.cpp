#include "modules/clouds/envelope/envelope_steps.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/parallel.h"

namespace cumulo::clouds::envelope {
namespace {

constexpr double kSqrt2 = 1.4142135623730951;

// One line of the 2D transform: f[q] (kNoSite: no site) -> d[q] = min_p (q - p)^2 + f[p], idx[q] = fidx[argmin].
// Only sites enter the lower envelope, so a line without any keeps kNoSite and -1 exactly.
void transform_line(const double* f, const int32_t* fidx, int n, double* d, int32_t* idx, std::vector<int>& v,
                    std::vector<double>& z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] >= kNoSite) continue;
    double s = 0.0;
    while (k >= 0) {
      const int p = v[size_t(k)];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[size_t(k)]) break;
      --k;
    }
    ++k;
    v[size_t(k)] = q;
    z[size_t(k)] = k == 0 ? -std::numeric_limits<double>::infinity() : s;
    z[size_t(k) + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) {
    std::fill(d, d + n, kNoSite);
    std::fill(idx, idx + n, -1);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[size_t(j) + 1] < q) ++j;
    const int p = v[size_t(j)];
    d[q] = double(q - p) * (q - p) + f[p];
    idx[q] = fidx[p];
  }
}

// The lower bound of a ratio between texel (ix, iy) and any texel at least (dx, dy) texels away whose value rises at
// most `rise` above its own. At a single texel it is that pair's exact ratio, with the same rounding.
double ratio_bound(int dx, int dy, double rise, double texel_m) {
  const double ax = std::max(dx - 1, 0), ay = std::max(dy - 1, 0);
  const double d = std::sqrt(ax * ax + ay * ay);
  return d > 0.0 ? d * texel_m / rise : 0.0;
}

float round_ratio_down(double best, float cap) {
  if (best >= double(cap)) return cap;
  const double r = best * (1.0 - 1e-6);
  float f = float(r);
  if (double(f) > r) f = std::nextafter(f, 0.0f);
  return f;
}

}  // namespace

DistanceField distance_transform(const std::vector<uint8_t>& site, uint32_t n) {
  const size_t count = size_t(n) * n;
  DistanceField out;
  out.d2.assign(count, kNoSite);
  out.nearest.assign(count, -1);
  std::vector<double> row_d(count), f(n), d(n);
  std::vector<int32_t> row_i(count), fi(n), di(n);
  std::vector<int> v(n);
  std::vector<double> z(size_t(n) + 1);
  // Along x: each texel's nearest site in its row.
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      f[i] = site[size_t(j) * n + i] ? 0.0 : kNoSite;
      fi[i] = int32_t(size_t(j) * n + i);
    }
    transform_line(f.data(), fi.data(), int(n), &row_d[size_t(j) * n], &row_i[size_t(j) * n], v, z);
  }
  // Along z over the rows' results.
  for (uint32_t i = 0; i < n; ++i) {
    for (uint32_t j = 0; j < n; ++j) {
      f[j] = row_d[size_t(j) * n + i];
      fi[j] = row_i[size_t(j) * n + i];
    }
    transform_line(f.data(), fi.data(), int(n), d.data(), di.data(), v, z);
    for (uint32_t j = 0; j < n; ++j) {
      out.d2[size_t(j) * n + i] = d[j];
      out.nearest[size_t(j) * n + i] = di[j];
    }
  }
  return out;
}

std::vector<float> cone_ratios(const std::vector<float>& apex, const std::vector<float>& value, uint32_t n, float texel_m,
                               float cap) {
  // A max pyramid: level l's node (x, y) covers texels [x << l, (x + 1) << l) clipped to the map.
  std::vector<std::vector<float>> levels{value};
  std::vector<uint32_t> widths{n};
  while (widths.back() > 1) {
    const uint32_t w = widths.back(), h = (w + 1) / 2;
    const std::vector<float>& below = levels.back();
    std::vector<float> up(size_t(h) * h);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < h; ++x) {
        float m = -std::numeric_limits<float>::infinity();
        for (uint32_t cy = 2 * y; cy < std::min(2 * y + 2, w); ++cy)
          for (uint32_t cx = 2 * x; cx < std::min(2 * x + 2, w); ++cx) m = std::max(m, below[size_t(cy) * w + cx]);
        up[size_t(y) * h + x] = m;
      }
    levels.push_back(std::move(up));
    widths.push_back(h);
  }
  const int top = int(levels.size()) - 1;
  std::vector<float> out(value.size(), cap);
  const double texel = texel_m;

  parallel_for(
      n,
      [&](size_t row_begin, size_t row_end) {
        struct Node {
          int level, x, y;
          double bound;
        };
        std::vector<Node> stack;
        for (size_t iy = row_begin; iy < row_end; ++iy)
          for (uint32_t ix = 0; ix < n; ++ix) {
            const double v = apex[iy * n + ix];
            double best = cap;
            if (double(levels[size_t(top)][0]) <= v) continue;
            // A node's bound from its nearest point and highest value; +inf when nothing in it rises above v.
            auto bound = [&](int level, int x, int y) {
              const double rise = double(levels[size_t(level)][size_t(y) * widths[size_t(level)] + size_t(x)]) - v;
              if (!(rise > 0.0)) return std::numeric_limits<double>::infinity();
              const int x0 = x << level, y0 = y << level;
              const int x1 = std::min((x + 1) << level, int(n)) - 1, y1 = std::min((y + 1) << level, int(n)) - 1;
              const int dx = std::max({0, x0 - int(ix), int(ix) - x1}), dy = std::max({0, y0 - int(iy), int(iy) - y1});
              return ratio_bound(dx, dy, rise, texel);
            };
            stack.clear();
            stack.push_back({top, 0, 0, bound(top, 0, 0)});
            while (!stack.empty()) {
              const Node node = stack.back();
              stack.pop_back();
              if (node.bound >= best) continue;
              if (node.level == 0) {
                best = node.bound;
                continue;
              }
              Node children[4];
              int count = 0;
              const int cl = node.level - 1, cw = int(widths[size_t(cl)]);
              for (int cy = 2 * node.y; cy < std::min(2 * node.y + 2, cw); ++cy)
                for (int cx = 2 * node.x; cx < std::min(2 * node.x + 2, cw); ++cx) {
                  const double b = bound(cl, cx, cy);
                  if (!(b < best)) continue;
                  // Insertion by decreasing bound: the nearest ends on top of the stack, and a good ratio found
                  // early prunes the rest.
                  int at = count++;
                  for (; at > 0 && children[at - 1].bound < b; --at) children[at] = children[at - 1];
                  children[at] = {cl, cx, cy, b};
                }
              for (int c = 0; c < count; ++c) stack.push_back(children[c]);
            }
            out[iy * n + ix] = round_ratio_down(best, cap);
          }
      },
      8);
  return out;
}

void derive_envelope_steps(EnvelopeMaps& m) {
  const uint32_t n = m.resolution;
  const size_t count = size_t(n) * n;
  const double texel = m.texel_m;
  std::vector<uint8_t> covered(count), open(count);
  bool any = false;
  for (size_t k = 0; k < count; ++k) {
    covered[k] = m.shape[k].z > 0.0f;
    open[k] = !covered[k];
    any = any || covered[k];
  }
  const DistanceField to_covered = distance_transform(covered, n);
  const DistanceField to_open = distance_transform(open, n);

  m.edge_m.assign(count, -kFarDistanceM);
  m.min_bottom = m.max_top = 0.0f;
  if (any) {
    m.min_bottom = std::numeric_limits<float>::max();
    m.max_top = std::numeric_limits<float>::lowest();
  }
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const size_t k = size_t(j) * n + i;
      if (covered[k]) {
        m.min_bottom = std::min(m.min_bottom, m.shape[k].x);
        m.max_top = std::max(m.max_top, m.shape[k].y);
        // Past the map's border counts as outside: its nearest virtual centre is one step beyond the border texel.
        double d = std::min({double(i) + 1.0, double(n - i), double(j) + 1.0, double(n - j)});
        if (to_open.nearest[k] >= 0) d = std::min(d, std::sqrt(to_open.d2[k]));
        m.edge_m[k] = float((d - 0.5) * texel);
      } else if (any) {
        m.edge_m[k] = float(-(std::sqrt(to_covered.d2[k]) - 0.5) * texel);
        const glm::vec4 from = m.shape[size_t(to_covered.nearest[k])];
        m.shape[k] = glm::vec4(from.x, from.y, 0.0f, from.w);
      } else {
        m.shape[k] = glm::vec4(0.0f, 0.0f, 0.0f, 0.5f);
      }
    }

  // The bilinear shape at a point of texel (i, j) mixes the 3x3's values only, dilated ones included.
  m.steps.assign(count, glm::vec4(kEmptyTop, kEmptyBottom, kMaxConeRatio, kMaxConeRatio));
  std::vector<uint8_t> near(count, 0);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      bool has = false;
      float hi = std::numeric_limits<float>::lowest(), lo = std::numeric_limits<float>::max();
      for (uint32_t y = j > 0 ? j - 1 : 0; y <= std::min(j + 1, n - 1); ++y)
        for (uint32_t x = i > 0 ? i - 1 : 0; x <= std::min(i + 1, n - 1); ++x) {
          const glm::vec4& s = m.shape[size_t(y) * n + x];
          has = has || covered[size_t(y) * n + x];
          hi = std::max(hi, s.y);
          lo = std::min(lo, s.x);
        }
      const size_t k = size_t(j) * n + i;
      if (has) {
        m.steps[k].x = hi;
        m.steps[k].y = lo;
        near[k] = 1;
      }
    }

  const DistanceField to_near = distance_transform(near, n);
  m.distance_m.assign(count, kFarDistanceM);
  for (size_t k = 0; k < count; ++k)
    if (to_near.nearest[k] >= 0) {
      // Rounded down: where the offset is diagonal the bound is the squares' exact distance.
      const double d = std::max(0.0, std::sqrt(to_near.d2[k]) - kSqrt2) * texel;
      float f = float(d);
      if (double(f) > d) f = std::nextafter(f, 0.0f);
      m.distance_m[k] = f;
    }

  // The apexes: the 3x3's extreme Tc and Bc (a texel without any keeps its empty values).
  m.apex.assign(count, glm::vec2(kEmptyTop, kEmptyBottom));
  std::vector<float> tops(count), bottoms(count), top_apex(count), bottom_apex(count);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const size_t k = size_t(j) * n + i;
      glm::vec2 a(m.steps[k].x, m.steps[k].y);
      for (uint32_t y = j > 0 ? j - 1 : 0; y <= std::min(j + 1, n - 1); ++y)
        for (uint32_t x = i > 0 ? i - 1 : 0; x <= std::min(i + 1, n - 1); ++x) {
          const glm::vec4& o = m.steps[size_t(y) * n + x];
          if (o.x > kEmptyTop) a.x = std::max(a.x, o.x);
          if (o.y < kEmptyBottom) a.y = std::min(a.y, o.y);
        }
      m.apex[k] = a;
      tops[k] = m.steps[k].x;
      bottoms[k] = -m.steps[k].y;  // the downward cone is the upward one of the negated bottoms
      top_apex[k] = a.x;
      bottom_apex[k] = -a.y;
    }
  const std::vector<float> top_ratio = cone_ratios(top_apex, tops, n, m.texel_m, kMaxConeRatio);
  const std::vector<float> bottom_ratio = cone_ratios(bottom_apex, bottoms, n, m.texel_m, kMaxConeRatio);
  for (size_t k = 0; k < count; ++k) {
    m.steps[k].z = top_ratio[k];
    m.steps[k].w = bottom_ratio[k];
  }
}

}  // namespace cumulo::clouds::envelope
