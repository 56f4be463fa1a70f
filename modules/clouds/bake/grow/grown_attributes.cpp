#include "modules/clouds/bake/grow/grown_attributes.h"

#include <algorithm>
#include <cmath>

#include "engine/core/parallel.h"
#include "modules/clouds/volume/distance.h"

namespace cumulo::clouds::grow {

namespace {

float trilinear(const std::vector<float>& v, glm::uvec3 d, glm::vec3 p) {
  p = glm::clamp(p, glm::vec3(0.0f), glm::vec3(d) - 1.0f);
  const glm::uvec3 a = glm::min(glm::uvec3(p), glm::max(d, glm::uvec3(2)) - 2u);
  const glm::uvec3 b = glm::min(a + 1u, d - 1u);
  const glm::vec3 f = p - glm::vec3(a);
  auto at = [&](uint32_t x, uint32_t y, uint32_t z) { return v[x + size_t(d.x) * (y + size_t(d.y) * z)]; };
  const float c00 = glm::mix(at(a.x, a.y, a.z), at(b.x, a.y, a.z), f.x), c10 = glm::mix(at(a.x, b.y, a.z), at(b.x, b.y, a.z), f.x);
  const float c01 = glm::mix(at(a.x, a.y, b.z), at(b.x, a.y, b.z), f.x), c11 = glm::mix(at(a.x, b.y, b.z), at(b.x, b.y, b.z), f.x);
  return glm::mix(glm::mix(c00, c10, f.y), glm::mix(c01, c11, f.y), f.z);
}

float percentile(std::vector<float> v, float q) {
  if (v.empty()) return 0.0f;
  const size_t k = std::min(v.size() - 1, size_t(q * float(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + long(k), v.end());
  return v[k];
}

// Running max along one axis over +-r samples.
void max_filter_axis(std::vector<float>& v, glm::uvec3 d, int axis, int r) {
  const size_t stride = axis == 0 ? 1 : (axis == 1 ? d.x : size_t(d.x) * d.y);
  const uint32_t n = d[axis];
  const glm::uvec3 other = axis == 0 ? glm::uvec3(1, d.y, d.z) : (axis == 1 ? glm::uvec3(d.x, 1, d.z) : glm::uvec3(d.x, d.y, 1));
  const size_t lines = size_t(other.x) * other.y * other.z;
  std::vector<float> out(v.size());
  parallel_for(lines, [&](size_t b, size_t e) {
    std::vector<float> line(n);
    for (size_t l = b; l < e; ++l) {
      const uint32_t x = uint32_t(l % other.x), y = uint32_t((l / other.x) % other.y), z = uint32_t(l / (size_t(other.x) * other.y));
      const size_t base = x + size_t(d.x) * (y + size_t(d.y) * z);
      for (uint32_t i = 0; i < n; ++i) line[i] = v[base + i * stride];
      for (uint32_t i = 0; i < n; ++i) {
        float m = line[i];
        for (int k = std::max(0, int(i) - r); k <= std::min(int(n) - 1, int(i) + r); ++k) m = std::max(m, line[k]);
        out[base + i * stride] = m;
      }
    }
  }, 16);
  v.swap(out);
}

// Outside the cloud, attribute cells take the mean of their inside (or already filled) neighbours, a few
// rings deep, so trilinear samples at the surface do not blend in meaningless values.
void dilate(std::vector<float>& v, std::vector<uint8_t> known, glm::uvec3 d, int rings, float fallback) {
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<uint8_t> next = known;
    std::vector<float> out = v;
    for (uint32_t z = 0; z < d.z; ++z)
      for (uint32_t y = 0; y < d.y; ++y)
        for (uint32_t x = 0; x < d.x; ++x) {
          const size_t c = x + size_t(d.x) * (y + size_t(d.y) * z);
          if (known[c]) continue;
          float s = 0.0f;
          int m = 0;
          const int nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
          for (const auto& o : nb) {
            const int a = int(x) + o[0], b = int(y) + o[1], e = int(z) + o[2];
            if (a < 0 || b < 0 || e < 0 || a >= int(d.x) || b >= int(d.y) || e >= int(d.z)) continue;
            const size_t q = size_t(a) + size_t(d.x) * (size_t(b) + size_t(d.y) * size_t(e));
            if (known[q]) s += v[q], ++m;
          }
          if (m) out[c] = s / float(m), next[c] = 1;
        }
    v.swap(out);
    known.swap(next);
  }
  for (size_t c = 0; c < v.size(); ++c)
    if (!known[c]) v[c] = fallback;
}

void blur3(std::vector<float>& v, glm::uvec3 d) {
  for (int axis = 0; axis < 3; ++axis) {
    const size_t stride = axis == 0 ? 1 : (axis == 1 ? d.x : size_t(d.x) * d.y);
    std::vector<float> out(v.size());
    for (uint32_t z = 0; z < d.z; ++z)
      for (uint32_t y = 0; y < d.y; ++y)
        for (uint32_t x = 0; x < d.x; ++x) {
          const glm::uvec3 p(x, y, z);
          const size_t c = x + size_t(d.x) * (y + size_t(d.y) * z);
          const float lo = p[axis] > 0 ? v[c - stride] : v[c], hi = p[axis] + 1 < d[axis] ? v[c + stride] : v[c];
          out[c] = 0.25f * lo + 0.5f * v[c] + 0.25f * hi;
        }
    v.swap(out);
  }
}

}  // namespace

float AttributeGrid::sample(glm::vec3 p) const { return trilinear(values, dims, (p - origin) / spacing); }

float GrownModeling::signed_distance(glm::vec3 p) const {
  const glm::vec3 q = glm::clamp(p, sdf.origin, sdf.origin + glm::vec3(sdf.dims - 1u) * sdf.spacing);
  return sdf.sample(q) + glm::length(p - q);
}

std::shared_ptr<const GrownModeling> derive_modeling(const GrownCloud& g) {
  auto m = std::make_shared<GrownModeling>();
  const int f = std::max(1, int(std::ceil(g.cell / 8.0f - 1e-4f)));
  const float spacing = g.cell / float(f);
  const glm::uvec3 fd = (g.dims - 1u) * uint32_t(f) + 1u;
  const size_t fn = size_t(fd.x) * fd.y * fd.z;
  auto make = [&](AttributeGrid& a) {
    a.dims = fd, a.origin = g.origin, a.spacing = spacing;
    a.values.resize(fn);
  };
  make(m->sdf), make(m->profile_depth), make(m->detail_type), make(m->density_scale);
  m->bounds_min = g.origin;
  m->bounds_max = g.origin + glm::vec3(fd - 1u) * spacing;

  // Cloud water at the fine spacing and its iso-surface distance.
  std::vector<float> qf(fn);
  parallel_for(fd.z, [&](size_t b, size_t e) {
    for (size_t z = b; z < e; ++z)
      for (uint32_t y = 0; y < fd.y; ++y)
        for (uint32_t x = 0; x < fd.x; ++x)
          qf[x + size_t(fd.x) * (y + size_t(fd.y) * z)] = trilinear(g.cloud_water, g.dims, glm::vec3(x, y, z) / float(f));
  });
  std::vector<uint8_t> inside(fn);
  for (size_t c = 0; c < fn; ++c) inside[c] = qf[c] > g.iso;
  std::vector<float>& sdf = m->sdf.values;
  sdf = signed_distance_from_mask(inside, fd, spacing);
  const size_t sy = fd.x, sz = size_t(fd.x) * fd.y;
  for (uint32_t z = 1; z + 1 < fd.z; ++z)
    for (uint32_t y = 1; y + 1 < fd.y; ++y)
      for (uint32_t x = 1; x + 1 < fd.x; ++x) {
        const size_t c = x + sy * y + sz * z;
        const bool s = inside[c];
        if (inside[c - 1] == s && inside[c + 1] == s && inside[c - sy] == s && inside[c + sy] == s && inside[c - sz] == s &&
            inside[c + sz] == s)
          continue;
        const glm::vec3 grad(qf[c + 1] - qf[c - 1], qf[c + sy] - qf[c - sy], qf[c + sz] - qf[c - sz]);
        const float len = glm::length(grad) / (2.0f * spacing);
        if (len <= 0.0f) continue;
        const float d = (g.iso - qf[c]) / len;
        if (std::abs(d) < std::abs(sdf[c]) && (d > 0.0f) == !s) sdf[c] = d;
      }
  for (float& d : sdf)
    if (!std::isfinite(d)) d = d > 0.0f ? 4096.0f : -4096.0f;

  // Profile depth from the local thickness.
  std::vector<float>& depth = m->profile_depth.values;
  for (size_t c = 0; c < fn; ++c) depth[c] = std::max(0.0f, -sdf[c]);
  const int r = std::max(1, int(std::ceil(kThicknessRadius / spacing)));
  for (int axis = 0; axis < 3; ++axis) max_filter_axis(depth, fd, axis, r);
  for (float& d : depth) d = std::clamp(kThicknessFactor * d, kMinProfileDepth, kMaxProfileDepth);

  // Detail type and density scale on the solver's cells, then resampled.
  const size_t n = g.count();
  std::vector<float> cpos, wpos, gpos, qin;
  std::vector<uint8_t> cloud(n);
  for (size_t c = 0; c < n; ++c) {
    cloud[c] = g.cloud_water[c] > g.iso;
    if (!cloud[c]) continue;
    cpos.push_back(std::abs(g.condensation[c]));
    wpos.push_back(std::abs(g.vertical_velocity[c]));
    gpos.push_back(std::abs(g.growth[c]));
    qin.push_back(g.cloud_water[c]);
  }
  const float cref = std::max(percentile(cpos, 0.9f), 1e-12f), wref = std::max(percentile(wpos, 0.9f), 1e-6f);
  const float qmed = std::max(percentile(qin, 0.5f), 1e-9f);
  const float gref = std::max(percentile(gpos, 0.9f), 1e-14f);
  // Height within the cloud's column (0 at its base, 1 at its top): at the end of a run a cumulus's base still
  // condenses the inflow as strongly as its top, so the rates alone do not make bases wispy (measured: the top
  // third of a mediocris was 0.07 wispier than its bottom third without this term).
  std::vector<float> column_height(n, 0.5f);
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t i = 0; i < g.dims.x; ++i) {
      int lo = -1, hi = -1;
      for (uint32_t j = 0; j < g.dims.y; ++j)
        if (cloud[g.index(i, j, k)]) hi = int(j), lo = lo < 0 ? int(j) : lo;
      if (lo < 0) continue;
      for (int j = lo; j <= hi; ++j) column_height[g.index(i, uint32_t(j), k)] = hi > lo ? float(j - lo) / float(hi - lo) : 0.5f;
    }
  std::vector<float> type(n), dens(n);
  for (size_t c = 0; c < n; ++c) {
    const float cn = g.condensation[c] / cref, wn = g.vertical_velocity[c] / wref, gn = g.growth[c] / gref;
    const float rates = kGrowthWeight * gn + kCondensationWeight * cn + kUpdraftWeight * wn;
    type[c] = std::clamp(0.5f + 0.5f * ((1.0f - kHeightWeight) * rates + kHeightWeight * (2.0f * column_height[c] - 1.0f)),
                         0.0f, 1.0f);
    const float thin = std::clamp(g.cloud_water[c] / qmed, 0.0f, 1.0f);
    const float evaporating = std::clamp(-cn, 0.0f, 1.0f);
    dens[c] = (0.45f + 0.55f * thin) * (1.0f - 0.3f * evaporating);
  }
  dilate(type, cloud, g.dims, 4, 0.5f);
  dilate(dens, cloud, g.dims, 4, 0.5f);
  blur3(type, g.dims);
  parallel_for(fd.z, [&](size_t b, size_t e) {
    for (size_t z = b; z < e; ++z)
      for (uint32_t y = 0; y < fd.y; ++y)
        for (uint32_t x = 0; x < fd.x; ++x) {
          const size_t c = x + size_t(fd.x) * (y + size_t(fd.y) * z);
          const glm::vec3 p = glm::vec3(x, y, z) / float(f);
          m->detail_type.values[c] = std::clamp(trilinear(type, g.dims, p), 0.0f, 1.0f);
          m->density_scale.values[c] = std::clamp(trilinear(dens, g.dims, p), 0.0f, 1.0f);
        }
  });
  return m;
}

}  // namespace cumulo::clouds::grow
