#include "modules/clouds/bake/grid_sdf.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/memory_budget.h"
#include "engine/core/parallel.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/volume_file.h"
#include "modules/clouds/volume/nvdf.h"

#ifdef CUMULO_BAKE_HAS_SCENE
#include "engine/scene/gltf.h"
#endif

namespace cumulo::clouds::bake {

namespace {

constexpr uint32_t kMaxGridDim = 512;

// Squared distance from p to triangle abc (Ericson, "Real-Time Collision Detection" 5.1.5).
float point_triangle_distance2(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto len2 = [](glm::vec3 v) { return glm::dot(v, v); };
  if (d1 <= 0.0f && d2 <= 0.0f) return len2(ap);
  glm::vec3 bp = p - b;
  float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return len2(bp);
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return len2(p - (a + ab * (d1 / (d1 - d3))));
  glm::vec3 cp = p - c;
  float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return len2(cp);
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return len2(p - (a + ac * (d2 / (d2 - d6))));
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return len2(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  float denom = 1.0f / (va + vb + vc);
  return len2(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// x coordinates where the line {y = py, z = pz} crosses the triangles (2D barycentric test in y-z).
void row_crossings(const std::vector<glm::vec3>& t, float py, float pz, std::vector<float>& xs) {
  xs.clear();
  for (size_t i = 0; i + 2 < t.size(); i += 3) {
    const glm::vec3 &a = t[i], &b = t[i + 1], &c = t[i + 2];
    float ymin = std::min(a.y, std::min(b.y, c.y)), ymax = std::max(a.y, std::max(b.y, c.y));
    float zmin = std::min(a.z, std::min(b.z, c.z)), zmax = std::max(a.z, std::max(b.z, c.z));
    if (py < ymin || py > ymax || pz < zmin || pz > zmax) continue;
    float w0 = (b.y - py) * (c.z - pz) - (b.z - pz) * (c.y - py);
    float w1 = (c.y - py) * (a.z - pz) - (c.z - pz) * (a.y - py);
    float w2 = (a.y - py) * (b.z - pz) - (a.z - pz) * (b.y - py);
    if (!((w0 >= 0 && w1 >= 0 && w2 >= 0) || (w0 <= 0 && w1 <= 0 && w2 <= 0))) continue;
    float sum = w0 + w1 + w2;
    if (sum == 0.0f) continue;  // triangle seen edge-on
    xs.push_back((w0 * a.x + w1 * b.x + w2 * c.x) / sum);
  }
  std::sort(xs.begin(), xs.end());
}

}  // namespace

float GridSdf::sample(glm::vec3 p) const {
  glm::vec3 g = (p - origin) / spacing;
  glm::vec3 hi = glm::vec3(dims) - 1.0f;
  glm::vec3 c = glm::clamp(g, glm::vec3(0.0f), hi);
  float outside = glm::length(g - c) * spacing;
  glm::uvec3 i0 = glm::min(glm::uvec3(c), dims - 1u);
  glm::uvec3 i1 = glm::min(i0 + 1u, dims - 1u);
  glm::vec3 f = c - glm::vec3(i0);
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  float v00 = lerp(at(i0.x, i0.y, i0.z), at(i1.x, i0.y, i0.z), f.x);
  float v10 = lerp(at(i0.x, i1.y, i0.z), at(i1.x, i1.y, i0.z), f.x);
  float v01 = lerp(at(i0.x, i0.y, i1.z), at(i1.x, i0.y, i1.z), f.x);
  float v11 = lerp(at(i0.x, i1.y, i1.z), at(i1.x, i1.y, i1.z), f.x);
  return lerp(lerp(v00, v10, f.y), lerp(v01, v11, f.y), f.z) + outside;
}

Aabb grid_bounds(const GridSdf& g) {
  return {g.origin, g.origin + (glm::vec3(g.dims) - 1.0f) * g.spacing};
}

std::shared_ptr<GridSdf> voxelize_triangles(const std::vector<glm::vec3>& tris, float spacing) {
  if (tris.size() < 3 || tris.size() % 3 != 0) fail("mesh: no triangles to voxelize");
  Aabb box;
  for (const glm::vec3& p : tris) box.add(p);
  const float margin = 3.0f * spacing;
  auto grid = std::make_shared<GridSdf>();
  grid->spacing = spacing;
  grid->origin = box.min - margin;
  glm::vec3 ext = box.max - box.min + 2.0f * margin;
  for (int a = 0; a < 3; ++a) {
    float n = std::ceil(ext[a] / spacing) + 1.0f;
    if (n > kMaxGridDim) fail("mesh: %g samples along axis %d at resolution %g (at most %u; raise \"resolution\")", n, a, spacing, kMaxGridDim);
    grid->dims[a] = static_cast<uint32_t>(n);
  }
  const glm::uvec3 d = grid->dims;
  // inside + outside masks (2), two squared-distance fields (8), the values (4).
  check_memory_budget(saturating_product({d.x, d.y, d.z, 14}),
                      strf("mesh: a %ux%ux%u voxelization at resolution %g", d.x, d.y, d.z, spacing));
  const size_t count = size_t(d.x) * d.y * d.z;

  // Inside/outside: parity of crossings along x, majority of three slightly offset rays per row.
  std::vector<uint8_t> inside(count, 0);
  parallel_for(size_t(d.y) * d.z, [&](size_t b, size_t e) {
    std::vector<float> xs[3];
    for (size_t row = b; row < e; ++row) {
      uint32_t y = row % d.y, z = row / d.y;
      float py = grid->origin.y + y * spacing, pz = grid->origin.z + z * spacing;
      const float o = 0.013f * spacing;
      row_crossings(tris, py + o, pz + 0.7f * o, xs[0]);
      row_crossings(tris, py - 0.6f * o, pz + o, xs[1]);
      row_crossings(tris, py + 0.4f * o, pz - o, xs[2]);
      for (uint32_t x = 0; x < d.x; ++x) {
        float px = grid->origin.x + x * spacing;
        int votes = 0;
        for (auto& v : xs) votes += (std::lower_bound(v.begin(), v.end(), px) - v.begin()) & 1;
        inside[x + size_t(d.x) * (y + size_t(d.y) * z)] = votes >= 2;
      }
    }
  });

  // Far from the surface: exact EDT between inside and outside sample centres, surface halfway.
  std::vector<uint8_t> outside(count);
  for (size_t i = 0; i < count; ++i) outside[i] = !inside[i];
  glm::vec3 sp(spacing);
  std::vector<float> to_inside = squared_distance_to_mask(inside, d, sp), to_outside = squared_distance_to_mask(outside, d, sp);
  grid->values.resize(count);
  for (size_t i = 0; i < count; ++i) {
    float v = inside[i] ? -(std::sqrt(to_outside[i]) - 0.5f * spacing) : std::sqrt(to_inside[i]) - 0.5f * spacing;
    // No inside sample at all (an open or flat mesh) leaves +inf, which sample()'s lerp would turn
    // into NaN (inf - inf): cap it at the NVDF SDF range.
    grid->values[i] = std::isinf(v) ? std::copysign(kSdfRangeMax, v) : v;
  }

  // Near the surface: exact distances to the triangles (z slabs in parallel: no shared writes).
  const float band = 2.0f * spacing;
  parallel_for(d.z, [&](size_t zb, size_t ze) {
    for (size_t i = 0; i + 2 < tris.size(); i += 3) {
      Aabb tb;
      tb.add(tris[i]), tb.add(tris[i + 1]), tb.add(tris[i + 2]);
      tb = tb.expanded(band);
      glm::ivec3 lo = glm::max(glm::ivec3(glm::ceil((tb.min - grid->origin) / spacing)), glm::ivec3(0));
      glm::ivec3 hi = glm::min(glm::ivec3(glm::floor((tb.max - grid->origin) / spacing)), glm::ivec3(d) - 1);
      lo.z = std::max(lo.z, static_cast<int>(zb));
      hi.z = std::min(hi.z, static_cast<int>(ze) - 1);
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) {
            size_t k = x + size_t(d.x) * (y + size_t(d.y) * z);
            glm::vec3 p = grid->origin + glm::vec3(x, y, z) * spacing;
            float dist = std::sqrt(point_triangle_distance2(p, tris[i], tris[i + 1], tris[i + 2]));
            float cur = std::abs(grid->values[k]);
            if (dist < cur) grid->values[k] = inside[k] ? -dist : dist;
          }
    }
  });
  return grid;
}

std::shared_ptr<GridSdf> voxelize_gltf_file(const std::filesystem::path& path, float resolution) {
#ifdef CUMULO_BAKE_HAS_SCENE
  scene::Model model = scene::load_gltf(path);
  std::vector<glm::vec3> tris;
  for (const scene::MeshInstance& inst : model.instances) {
    const scene::Mesh& mesh = model.meshes[inst.mesh];
    for (uint32_t idx : mesh.indices) tris.push_back(glm::vec3(inst.world * glm::vec4(mesh.vertices[idx].position, 1.0f)));
  }
  if (tris.empty()) fail("%s: the glTF has no triangles", path.string().c_str());
  if (resolution <= 0.0f) {
    Aabb b;
    for (const glm::vec3& p : tris) b.add(p);
    glm::vec3 e = b.max - b.min;
    resolution = std::max(e.x, std::max(e.y, e.z)) / 64.0f;
  }
  return voxelize_triangles(tris, resolution);
#else
  (void)resolution;
  fail("%s: this build has no glTF loader (cumulo_scene), so mesh edits cannot be baked", path.string().c_str());
#endif
}

std::shared_ptr<GridSdf> load_volume_sdf(const std::filesystem::path& path, float iso) {
  Volume v = load_volume(path);
  const std::string what = path.string();
  auto grid = std::make_shared<GridSdf>();
  grid->dims = v.size;
  grid->spacing = v.voxel_size;
  glm::vec3 spacing = (v.bounds_max - v.bounds_min) / glm::vec3(v.size);
  grid->origin = v.bounds_min + 0.5f * spacing;
  const size_t count = size_t(v.size.x) * v.size.y * v.size.z;
  grid->values.resize(count);
  int sdf = v.find_channel(kSignedDistance);
  if (sdf >= 0) {
    for (uint32_t z = 0; z < v.size.z; ++z)
      for (uint32_t y = 0; y < v.size.y; ++y)
        for (uint32_t x = 0; x < v.size.x; ++x)
          grid->values[x + size_t(v.size.x) * (y + size_t(v.size.y) * z)] = v.decoded(x, y, z, sdf);
    return grid;
  }
  uint32_t prof = v.channel(kDimensionalProfile, what);
  std::vector<uint8_t> inside(count), outside(count);
  for (uint32_t z = 0; z < v.size.z; ++z)
    for (uint32_t y = 0; y < v.size.y; ++y)
      for (uint32_t x = 0; x < v.size.x; ++x) {
        size_t i = x + size_t(v.size.x) * (y + size_t(v.size.y) * z);
        inside[i] = v.texel(x, y, z, prof) > iso;
        outside[i] = !inside[i];
      }
  std::vector<float> ti = squared_distance_to_mask(inside, v.size, spacing),
                     to = squared_distance_to_mask(outside, v.size, spacing);
  float h = 0.5f * std::min(spacing.x, std::min(spacing.y, spacing.z));
  for (size_t i = 0; i < count; ++i) {
    float d = inside[i] ? -(std::sqrt(to[i]) - h) : std::sqrt(ti[i]) - h;
    grid->values[i] = std::clamp(d, kSdfRangeMin, kSdfRangeMax);
  }
  return grid;
}

}  // namespace cumulo::clouds::bake
