#include "engine/render/mesh_lod.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/core/parallel.h"

namespace cumulo::render {
namespace {

scene::Bounds bounds_of(const scene::Mesh& mesh, const std::vector<uint32_t>& indices) {
  scene::Bounds b;
  for (uint32_t i : indices) b.add(mesh.vertices[i].position);
  return b;
}

// The axes of a height field: h the height, u and v the plane it stands over.
struct Axes {
  int u = 0, v = 2, h = 1;
};

// True when every triangle faces the same way along a.h (the chunk is a height field over u, v).
bool is_height_field(const scene::Mesh& mesh, const std::vector<uint32_t>& tris, const Axes& a) {
  int sign = 0;
  for (size_t i = 0; i < tris.size(); i += 3) {
    const glm::vec3 p0 = mesh.vertices[tris[i]].position, p1 = mesh.vertices[tris[i + 1]].position,
                    p2 = mesh.vertices[tris[i + 2]].position;
    const float n = glm::cross(p1 - p0, p2 - p0)[a.h];
    const int sn = n > 0.0f ? 1 : n < 0.0f ? -1 : 0;
    if (sn == 0) return false;
    if (sign == 0) sign = sn;
    if (sn != sign) return false;
  }
  return sign != 0;
}

// How far (along a.h) a level strays from the full chunk of a height field: the largest difference of the two
// surfaces' heights at the full chunk's vertices and edge midpoints (the simplified surface's triangles binned
// in a 16 x 16 grid over the chunk). Negative when a point finds no triangle (not expected: the border is locked).
float measured_error(const scene::Mesh& mesh, const std::vector<uint32_t>& vertices,
                     const std::vector<std::pair<uint32_t, uint32_t>>& edges, const uint32_t* level, size_t level_count,
                     const scene::Bounds& box, const Axes& a) {
  constexpr int kGrid = 16;
  const float u0 = box.min[a.u], v0 = box.min[a.v];
  const float du = std::max(box.max[a.u] - u0, 1e-6f) / kGrid, dv = std::max(box.max[a.v] - v0, 1e-6f) / kGrid;
  auto cell = [&](float x, float lo, float d) { return std::clamp(int((x - lo) / d), 0, kGrid - 1); };
  std::vector<std::vector<uint32_t>> bins(kGrid * kGrid);
  for (size_t t = 0; t < level_count; t += 3) {
    float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = mesh.vertices[level[t + k]].position;
      umin = std::min(umin, p[a.u]), umax = std::max(umax, p[a.u]), vmin = std::min(vmin, p[a.v]), vmax = std::max(vmax, p[a.v]);
    }
    for (int j = cell(vmin, v0, dv); j <= cell(vmax, v0, dv); ++j)
      for (int i = cell(umin, u0, du); i <= cell(umax, u0, du); ++i) bins[j * kGrid + i].push_back(uint32_t(t));
  }
  auto height_at = [&](float x, float y, float& h) {
    for (uint32_t t : bins[cell(y, v0, dv) * kGrid + cell(x, u0, du)]) {
      const glm::vec3 p0 = mesh.vertices[level[t]].position, p1 = mesh.vertices[level[t + 1]].position,
                      p2 = mesh.vertices[level[t + 2]].position;
      const float det = (p1[a.v] - p2[a.v]) * (p0[a.u] - p2[a.u]) + (p2[a.u] - p1[a.u]) * (p0[a.v] - p2[a.v]);
      if (std::abs(det) < 1e-12f) continue;
      const float w0 = ((p1[a.v] - p2[a.v]) * (x - p2[a.u]) + (p2[a.u] - p1[a.u]) * (y - p2[a.v])) / det;
      const float w1 = ((p2[a.v] - p0[a.v]) * (x - p2[a.u]) + (p0[a.u] - p2[a.u]) * (y - p2[a.v])) / det;
      const float w2 = 1.0f - w0 - w1;
      constexpr float kEps = -1e-4f;
      if (w0 >= kEps && w1 >= kEps && w2 >= kEps) {
        h = w0 * p0[a.h] + w1 * p1[a.h] + w2 * p2[a.h];
        return true;
      }
    }
    return false;
  };
  float worst = 0.0f;
  auto probe = [&](const glm::vec3& p) {
    float h = 0.0f;
    if (!height_at(p[a.u], p[a.v], h)) return false;
    worst = std::max(worst, std::abs(h - p[a.h]));
    return true;
  };
  for (uint32_t i : vertices)
    if (!probe(mesh.vertices[i].position)) return -1.0f;
  for (const auto& [i, j] : edges)
    if (!probe(0.5f * (mesh.vertices[i].position + mesh.vertices[j].position))) return -1.0f;
  return worst;
}

struct BuiltChunk {
  MeshChunk chunk;                // first_index relative to `indices`
  std::vector<uint32_t> indices;  // its levels, one after another
};

// The chunk's levels: level 0 its own triangles, then each simplified from level 0 to about
// a quarter of the one before, until the simplifier stops gaining. A level's error is measured where the chunk is
// a height field (1.25 x the largest difference at the full surface's vertices and edge midpoints, for what
// lies between), else meshoptimizer's estimate x 3 (a distance estimate, not a bound).
BuiltChunk build_chunk(const scene::Mesh& mesh, std::vector<uint32_t> tris, float scale, const Axes& axes,
                       const MeshLodSettings& s) {
  BuiltChunk built;
  MeshChunk& chunk = built.chunk;
  std::vector<uint32_t>& out_indices = built.indices;
  chunk.bounds = bounds_of(mesh, tris);
  const size_t vertex_count = mesh.vertices.size();
  meshopt_optimizeVertexCache(tris.data(), tris.data(), tris.size(), vertex_count);
  auto append = [&](const std::vector<uint32_t>& level, float error) {
    chunk.levels.push_back({uint32_t(out_indices.size()), uint32_t(level.size()), error});
    out_indices.insert(out_indices.end(), level.begin(), level.end());
  };
  append(tris, 0.0f);
  const bool height_field = is_height_field(mesh, tris, axes);
  std::vector<uint32_t> vertices;  // the full chunk's, each once, and its edges: where a level's error is probed
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  if (height_field) {
    vertices.assign(tris.begin(), tris.end());
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    for (size_t i = 0; i < tris.size(); i += 3)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = tris[i + k], b = tris[i + (k + 1) % 3];
        edges.emplace_back(std::min(a, b), std::max(a, b));
      }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  }
  std::vector<uint32_t> level(tris.size());
  size_t previous = tris.size();
  float previous_error = 0.0f;
  for (uint32_t l = 1; l < s.max_levels; ++l) {
    const size_t target = std::max<size_t>(3, previous / 4 / 3 * 3);
    float relative_error = 0.0f;
    level.resize(tris.size());
    const size_t n = meshopt_simplify(level.data(), tris.data(), tris.size(), &mesh.vertices[0].position.x, vertex_count,
                                      sizeof(scene::Vertex), target, 1.0f, meshopt_SimplifyLockBorder, &relative_error);
    if (n == 0 || n * 5 > previous * 4) break;  // less than a fifth fewer: the border holds it
    level.resize(n);
    meshopt_optimizeVertexCache(level.data(), level.data(), n, vertex_count);
    const float measured = height_field ? measured_error(mesh, vertices, edges, level.data(), n, chunk.bounds, axes) : -1.0f;
    const float error = measured >= 0.0f ? 1.25f * measured : 3.0f * relative_error * scale;
    previous_error = std::max(previous_error, error);
    append(level, previous_error);
    previous = n;
  }
  return built;
}

}  // namespace

ChunkedMesh build_mesh_lods(const scene::Mesh& mesh, const MeshLodSettings& s) {
  ChunkedMesh out;
  const size_t triangles = mesh.indices.size() / 3;
  if (triangles == 0 || mesh.vertices.empty()) return out;
  if (triangles < s.min_triangles) {
    out.indices = mesh.indices;
    out.chunks.push_back({mesh.bounds.empty() ? bounds_of(mesh, mesh.indices) : mesh.bounds,
                          {{0, uint32_t(mesh.indices.size()), 0.0f}}});
    return out;
  }
  const float scale = meshopt_simplifyScale(&mesh.vertices[0].position.x, mesh.vertices.size(), sizeof(scene::Vertex));
  // The grid on the two widest axes of the mesh's box (x and z for a terrain), cells by triangle centroid.
  const scene::Bounds box = bounds_of(mesh, mesh.indices);
  const glm::vec3 size = box.size();
  std::array<int, 3> axes{0, 1, 2};
  std::sort(axes.begin(), axes.end(), [&](int a, int b) { return size[a] > size[b]; });
  const int u = axes[0], v = axes[1];
  const Axes field{u, v, axes[2]};
  const uint32_t g = std::max(1u, uint32_t(std::lround(std::sqrt(double(triangles) / double(std::max(1u, s.chunk_triangles))))));
  std::vector<std::vector<uint32_t>> cells(size_t(g) * g);
  for (size_t t = 0; t < triangles; ++t) {
    const uint32_t* tri = &mesh.indices[3 * t];
    const glm::vec3 c = (mesh.vertices[tri[0]].position + mesh.vertices[tri[1]].position + mesh.vertices[tri[2]].position) / 3.0f;
    auto cell = [&](int axis) {
      const float f = size[axis] > 0.0f ? (c[axis] - box.min[axis]) / size[axis] : 0.0f;
      return std::min(g - 1, uint32_t(std::max(0.0f, f * float(g))));
    };
    auto& list = cells[size_t(cell(v)) * g + cell(u)];
    list.insert(list.end(), tri, tri + 3);
  }
  cells.erase(std::remove_if(cells.begin(), cells.end(), [](const auto& c) { return c.empty(); }), cells.end());
  std::vector<BuiltChunk> built(cells.size());
  parallel_for(cells.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) built[i] = build_chunk(mesh, std::move(cells[i]), scale, field, s);
  });
  for (BuiltChunk& b : built) {  // in cell order: the result does not depend on the thread count
    const uint32_t base = uint32_t(out.indices.size());
    for (MeshLodLevel& l : b.chunk.levels) l.first_index += base;
    out.indices.insert(out.indices.end(), b.indices.begin(), b.indices.end());
    out.chunks.push_back(std::move(b.chunk));
  }
  return out;
}

uint32_t choose_level(const MeshChunk& chunk, float world_scale, float distance, float pixels_per_unit, float max_error_px) {
  if (max_error_px <= 0.0f || chunk.levels.empty()) return 0;
  uint32_t best = 0;
  for (uint32_t l = 1; l < chunk.levels.size(); ++l) {
    const float px = chunk.levels[l].error * world_scale * pixels_per_unit / std::max(distance, 1e-3f);
    if (px > max_error_px) break;  // errors grow with the level
    best = l;
  }
  return best;
}

void select_chunk_draws(const std::vector<MeshChunk>& chunks, const glm::mat4& world, const scene::Frustum& frustum,
                        const glm::vec3& camera_pos, float pixels_per_unit, float max_error_px, std::vector<ChunkDraw>& out) {
  const float world_scale = std::max({glm::length(glm::vec3(world[0])), glm::length(glm::vec3(world[1])),
                                      glm::length(glm::vec3(world[2]))});
  for (const MeshChunk& chunk : chunks) {
    if (chunk.levels.empty()) continue;
    const scene::Bounds wb = chunk.bounds.transformed(world);
    if (chunks.size() > 1 && !frustum.intersects(wb)) continue;
    const uint32_t l = choose_level(chunk, world_scale, distance_to_box(wb, camera_pos), pixels_per_unit, max_error_px);
    out.push_back({chunk.levels[l].first_index, chunk.levels[l].index_count, l});
  }
}

float distance_to_box(const scene::Bounds& box, const glm::vec3& p) {
  const glm::vec3 d = glm::max(glm::max(box.min - p, p - box.max), glm::vec3(0.0f));
  return glm::length(d);
}

}  // namespace cumulo::render
