#include "engine/render/mesh_lod.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

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

// A border edge of a triangle list (an edge of one triangle only), as that triangle winds it (a to b), with
// the triangle's third corner c.
struct BorderEdge {
  uint32_t a, b, c;
};

std::vector<BorderEdge> border_edges(const uint32_t* tris, size_t count) {
  std::unordered_map<uint64_t, int> uses;  // undirected edge -> how many triangles have it
  auto key = [](uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); };
  for (size_t t = 0; t + 2 < count; t += 3)
    for (int k = 0; k < 3; ++k) ++uses[key(tris[t + k], tris[t + (k + 1) % 3])];
  std::vector<BorderEdge> out;
  for (size_t t = 0; t + 2 < count; t += 3)
    for (int k = 0; k < 3; ++k)
      if (uses[key(tris[t + k], tris[t + (k + 1) % 3])] == 1) out.push_back({tris[t + k], tris[t + (k + 1) % 3], tris[t + (k + 2) % 3]});
  return out;
}

// A height field's triangles binned in a 16 x 16 grid over `box`, for the height above a point.
class SurfaceLookup {
 public:
  SurfaceLookup(const scene::Mesh& mesh, const uint32_t* tris, size_t count, const scene::Bounds& box, const Axes& a)
      : mesh_(mesh), tris_(tris), a_(a), u0_(box.min[a.u]), v0_(box.min[a.v]),
        du_(std::max(box.max[a.u] - u0_, 1e-6f) / kGrid), dv_(std::max(box.max[a.v] - v0_, 1e-6f) / kGrid),
        bins_(kGrid * kGrid) {
    for (size_t t = 0; t < count; t += 3) {
      float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = mesh.vertices[tris[t + k]].position;
        umin = std::min(umin, p[a.u]), umax = std::max(umax, p[a.u]), vmin = std::min(vmin, p[a.v]), vmax = std::max(vmax, p[a.v]);
      }
      for (int j = cell(vmin, v0_, dv_); j <= cell(vmax, v0_, dv_); ++j)
        for (int i = cell(umin, u0_, du_); i <= cell(umax, u0_, du_); ++i) bins_[j * kGrid + i].push_back(uint32_t(t));
    }
  }
  // The height above (x, y) and the slope (rise over run) of the triangle there; false where none is.
  bool height_at(float x, float y, float& h, float& slope) const {
    for (uint32_t t : bins_[cell(y, v0_, dv_) * kGrid + cell(x, u0_, du_)]) {
      const glm::vec3 p0 = mesh_.vertices[tris_[t]].position, p1 = mesh_.vertices[tris_[t + 1]].position,
                      p2 = mesh_.vertices[tris_[t + 2]].position;
      const int u = a_.u, v = a_.v;
      const float det = (p1[v] - p2[v]) * (p0[u] - p2[u]) + (p2[u] - p1[u]) * (p0[v] - p2[v]);
      if (std::abs(det) < 1e-12f) continue;
      const float w0 = ((p1[v] - p2[v]) * (x - p2[u]) + (p2[u] - p1[u]) * (y - p2[v])) / det;
      const float w1 = ((p2[v] - p0[v]) * (x - p2[u]) + (p0[u] - p2[u]) * (y - p2[v])) / det;
      const float w2 = 1.0f - w0 - w1;
      constexpr float kEps = -1e-4f;
      if (w0 >= kEps && w1 >= kEps && w2 >= kEps) {
        h = w0 * p0[a_.h] + w1 * p1[a_.h] + w2 * p2[a_.h];
        const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
        slope = std::sqrt(n[u] * n[u] + n[v] * n[v]) / std::max(std::abs(n[a_.h]), 1e-12f);
        return true;
      }
    }
    return false;
  }

 private:
  static constexpr int kGrid = 16;
  static int cell(float x, float lo, float d) { return std::clamp(int((x - lo) / d), 0, kGrid - 1); }
  const scene::Mesh& mesh_;
  const uint32_t* tris_;
  Axes a_;
  float u0_, v0_, du_, dv_;
  std::vector<std::vector<uint32_t>> bins_;
};

// A contour line's piece across one triangle, in the plane of axes u, v.
struct Segment {
  glm::vec2 a, b;
};

std::vector<Segment> contour_segments(const scene::Mesh& mesh, const uint32_t* tris, size_t count, const Axes& ax, float c) {
  std::vector<Segment> out;
  if (!std::isfinite(c)) return out;
  for (size_t t = 0; t < count; t += 3) {
    glm::vec2 ends[2];
    int found = 0;
    for (int k = 0; k < 3 && found < 2; ++k) {
      const glm::vec3 pi = mesh.vertices[tris[t + k]].position, pj = mesh.vertices[tris[t + (k + 1) % 3]].position;
      if ((pi[ax.h] - c) * (pj[ax.h] - c) < 0.0f) {
        const glm::vec3 p = glm::mix(pi, pj, (c - pi[ax.h]) / (pj[ax.h] - pi[ax.h]));
        ends[found++] = {p[ax.u], p[ax.v]};
      }
    }
    if (found == 2) out.push_back({ends[0], ends[1]});
  }
  return out;
}

float distance_to_segment(const glm::vec2& p, const Segment& s) {
  const glm::vec2 d = s.b - s.a;
  const float len2 = glm::dot(d, d);
  const float t = len2 > 0.0f ? std::clamp(glm::dot(p - s.a, d) / len2, 0.0f, 1.0f) : 0.0f;
  return glm::length(p - (s.a + t * d));
}

// The farthest any point of `from` (its segments' ends and 7 points between) lies from the line `to`; 0 when
// either is empty.
float farthest(const std::vector<Segment>& from, const std::vector<Segment>& to) {
  if (from.empty() || to.empty()) return 0.0f;
  float worst = 0.0f;
  for (const Segment& s : from)
    for (int i = 0; i <= 8; ++i) {
      const glm::vec2 p = glm::mix(s.a, s.b, float(i) / 8.0f);
      float nearest = 1e30f;
      for (const Segment& t : to) nearest = std::min(nearest, distance_to_segment(p, t));
      worst = std::max(worst, nearest);
    }
  return worst;
}

// How far (along a.h) a level strays from the full chunk of a height field: the largest difference of the two
// surfaces' heights at the full chunk's vertices and edge midpoints. With a finite `contour` (a coastline),
// also how far the level moves that line: the distance, each way, between the level's contour line and the
// full one (`full_contour`), and where a point changes sides, its height difference over the flatter slope
// (an island that appears or goes, with no line near it in this chunk). Negative when a point finds no
// triangle (the level's outline moved). `border`: the largest height difference at the points flagged in
// `on_border` (the full chunk's border vertices and edges).
struct MeasuredError {
  float error = -1.0f, border = 0.0f;
};
MeasuredError measured_error(const scene::Mesh& mesh, const std::vector<uint32_t>& vertices,
                             const std::vector<std::pair<uint32_t, uint32_t>>& edges, const std::vector<uint8_t>& on_border,
                             const std::vector<Segment>& full_contour, const uint32_t* level, size_t level_count,
                             const scene::Bounds& box, const Axes& a, float contour) {
  const SurfaceLookup lookup(mesh, level, level_count, box, a);
  constexpr float kFlattest = 0.05f;  // a beach flatter than 1 in 20 counts as 1 in 20
  float worst = 0.0f, border = 0.0f;
  auto probe = [&](const glm::vec3& p, const glm::vec3& normal, bool at_border) {
    float h = 0.0f, level_slope = 0.0f;
    if (!lookup.height_at(p[a.u], p[a.v], h, level_slope)) return false;
    const float dh = std::abs(h - p[a.h]);
    worst = std::max(worst, dh);
    if (at_border) border = std::max(border, dh);
    if ((p[a.h] - contour) * (h - contour) < 0.0f) {  // the point changed sides (false for a NAN contour)
      const float len = glm::length(normal), nh = len > 1e-6f ? std::abs(normal[a.h]) / len : 0.7071f;
      const float full_slope = std::sqrt(std::max(0.0f, 1.0f - nh * nh)) / std::max(nh, 1e-3f);
      worst = std::max(worst, dh / std::max(std::min(full_slope, level_slope), kFlattest));
    }
    return true;
  };
  for (size_t k = 0; k < vertices.size(); ++k)
    if (!probe(mesh.vertices[vertices[k]].position, mesh.vertices[vertices[k]].normal, on_border[k])) return {};
  for (size_t k = 0; k < edges.size(); ++k) {
    const auto [i, j] = edges[k];
    const glm::vec3 pi = mesh.vertices[i].position, pj = mesh.vertices[j].position;
    if (!probe(0.5f * (pi + pj), mesh.vertices[i].normal + mesh.vertices[j].normal, on_border[vertices.size() + k])) return {};
  }
  // How far the level's contour line lies from the full one, each way (the lines sampled along their segments).
  if (!full_contour.empty()) {
    const std::vector<Segment> level_contour = contour_segments(mesh, level, level_count, a, contour);
    worst = std::max({worst, farthest(level_contour, full_contour), farthest(full_contour, level_contour)});
  }
  return {worst, border};
}

struct BuiltChunk {
  MeshChunk chunk;                            // errors only: build_mesh_lods places the levels
  std::vector<std::vector<uint32_t>> levels;  // each level's triangles
  float border_error = 0.0f;  // the most any level strays from the full surface on the chunk's border
};

// The chunk's levels: level 0 its own triangles, then each simplified from level 0 to about
// a quarter of the one before, until the simplifier stops gaining. A level's error is measured where the chunk is
// a height field (1.25 x the largest difference at the full surface's vertices and edge midpoints, for what
// lies between), else meshoptimizer's estimate x 3 (a distance estimate, not a bound).
// With `skirted` (the mesh is a height field, build_mesh_lods hangs skirts from every level's border) the
// border simplifies with the rest; a level that no longer covers every point of the full chunk (its outline
// moved) is not kept, so the skirts only ever close vertical gaps.
BuiltChunk build_chunk(const scene::Mesh& mesh, std::vector<uint32_t> tris, float scale, const Axes& axes,
                       const MeshLodSettings& s, bool skirted, const glm::vec3* steer) {
  BuiltChunk built;
  MeshChunk& chunk = built.chunk;
  chunk.bounds = bounds_of(mesh, tris);
  const size_t vertex_count = mesh.vertices.size();
  meshopt_optimizeVertexCache(tris.data(), tris.data(), tris.size(), vertex_count);
  auto append = [&](const std::vector<uint32_t>& level, float error) {
    chunk.levels.push_back({0, uint32_t(level.size()), error});
    built.levels.push_back(level);
  };
  append(tris, 0.0f);
  const bool height_field = is_height_field(mesh, tris, axes);
  std::vector<uint32_t> vertices;  // the full chunk's, each once, and its edges: where a level's error is probed
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  std::vector<uint8_t> on_border;  // per vertex, then per edge: on the chunk's border (an edge of one triangle)
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
    on_border.assign(vertices.size() + edges.size(), 0);
    for (const BorderEdge& e : border_edges(tris.data(), tris.size())) {
      for (uint32_t v : {e.a, e.b}) on_border[size_t(std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin())] = 1;
      const auto edge = std::make_pair(std::min(e.a, e.b), std::max(e.a, e.b));
      on_border[vertices.size() + size_t(std::lower_bound(edges.begin(), edges.end(), edge) - edges.begin())] = 1;
    }
  }
  const std::vector<Segment> full_contour =
      height_field ? contour_segments(mesh, tris.data(), tris.size(), axes, s.contour) : std::vector<Segment>{};
  std::vector<uint32_t> level(tris.size());
  size_t previous = tris.size();
  float previous_error = 0.0f;
  for (uint32_t l = 1; l < s.max_levels; ++l) {
    const size_t target = std::max<size_t>(3, previous / 4 / 3 * 3);
    float relative_error = 0.0f;
    level.resize(tris.size());
    const unsigned options = skirted && height_field ? 0u : unsigned(meshopt_SimplifyLockBorder);
    const size_t n = steer ? meshopt_simplify(level.data(), tris.data(), tris.size(), &steer[0].x, vertex_count,
                                              sizeof(glm::vec3), target, 1.0f, options, &relative_error)
                           : meshopt_simplify(level.data(), tris.data(), tris.size(), &mesh.vertices[0].position.x,
                                              vertex_count, sizeof(scene::Vertex), target, 1.0f, options, &relative_error);
    if (n == 0 || n * 5 > previous * 4) break;  // less than a fifth fewer: the border holds it
    level.resize(n);
    meshopt_optimizeVertexCache(level.data(), level.data(), n, vertex_count);
    const MeasuredError measured =
        height_field ? measured_error(mesh, vertices, edges, on_border, full_contour, level.data(), n, chunk.bounds, axes, s.contour)
                     : MeasuredError{};
    if (!options && measured.error < 0.0f) break;  // the outline moved: a hole no skirt closes
    const float error = measured.error >= 0.0f ? 1.25f * measured.error : 3.0f * relative_error * scale;
    built.border_error = std::max(built.border_error, measured.border);
    previous_error = std::max(previous_error, error);
    append(level, previous_error);
    previous = n;
  }
  return built;
}

// A wall hanging from every border edge of `tris` (an edge of one triangle) to the lowered copies of its two
// vertices, facing away from the triangle: it is seen only through a gap between this border and a
// neighbour's, from the neighbour's side.
template <typename Lowered>
void append_skirt(const scene::Mesh& mesh, const std::vector<uint32_t>& tris, const glm::vec3& down, Lowered&& lowered,
                  std::vector<uint32_t>& out) {
  for (const auto& [a, b, c] : border_edges(tris.data(), tris.size())) {
    const uint32_t la = lowered(a), lb = lowered(b);
    const glm::vec3 pa = mesh.vertices[a].position, pb = mesh.vertices[b].position, pc = mesh.vertices[c].position;
    // (a, la, b) faces along down x (b - a): keep the winding that faces away from the triangle's third vertex.
    if (glm::dot(glm::cross(down, pb - pa), pa - pc) >= 0.0f) out.insert(out.end(), {a, la, b, b, la, lb});
    else out.insert(out.end(), {a, b, la, b, lb, la});
  }
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
  // A height field shades from its normal texture whichever way it faces; it hangs skirts only when it stands
  // over x and z (a terrain, glTF's y up): a wall's skirts would stick out sideways behind it.
  const bool height_field = is_height_field(mesh, mesh.indices, field);
  if (height_field) out.normals = build_height_field_normals(mesh, mesh.indices, field.u, field.v, field.h);
  const bool skirted = height_field && field.h == 1;
  // Where a contour shows (a coastline), the simplifier sees the surface steepened across it, so it keeps the
  // vertices that hold the line in place (the levels' errors are measured on the real surface).
  std::vector<glm::vec3> steer;
  if (skirted && std::isfinite(s.contour)) {
    // A step of 5 % of the height range, 0.25 % of the range wide: of the widths tried on the sample terrain
    // (0.025 % to 5 %), the one whose levels met the same errors with the fewest triangles.
    const float a = 0.05f * std::max(size[field.h], 1e-3f), w = 0.05f * a;
    steer.reserve(mesh.vertices.size());
    for (const scene::Vertex& v : mesh.vertices) {
      glm::vec3 p = v.position;
      p[field.h] += a * std::tanh((p[field.h] - s.contour) / w);
      steer.push_back(p);
    }
  }
  std::vector<BuiltChunk> built(cells.size());
  parallel_for(cells.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      built[i] = build_chunk(mesh, std::move(cells[i]), scale, field, s, skirted, steer.empty() ? nullptr : steer.data());
  });
  // Two neighbours' borders (the same line at full detail) are at most the sum of their levels' heights off the
  // full surface there apart: a skirt twice the largest such height, hung from every level's border, closes
  // any gap between them (for a neighbour in another mesh of the same terrain, its border as far off as this
  // mesh's). Measured at the full border's vertices and edge midpoints, with the levels' 1.25 margin.
  float largest = 0.0f;
  for (const BuiltChunk& b : built) largest = std::max(largest, b.border_error);
  out.skirt_depth = skirted ? 2.5f * largest : 0.0f;
  glm::vec3 down(0.0f);
  if (out.skirt_depth > 0.0f) {
    const glm::vec3 p0 = mesh.vertices[mesh.indices[0]].position, p1 = mesh.vertices[mesh.indices[1]].position,
                    p2 = mesh.vertices[mesh.indices[2]].position;
    down[field.h] = glm::cross(p1 - p0, p2 - p0)[field.h] > 0.0f ? -1.0f : 1.0f;  // against the way the surface faces
  }
  std::unordered_map<uint32_t, uint32_t> skirt_vertex;  // a border vertex -> its copy `skirt_depth` below
  auto lowered = [&](uint32_t i) {
    auto [it, added] = skirt_vertex.try_emplace(i, uint32_t(mesh.vertices.size() + out.skirt_vertices.size()));
    if (added) {
      scene::Vertex v = mesh.vertices[i];
      v.position += down * out.skirt_depth;
      out.skirt_vertices.push_back(v);
    }
    return it->second;
  };
  for (BuiltChunk& b : built) {  // in cell order: the result does not depend on the thread count
    for (size_t l = 0; l < b.levels.size(); ++l) {
      MeshLodLevel& level = b.chunk.levels[l];
      level.first_index = uint32_t(out.indices.size());
      out.indices.insert(out.indices.end(), b.levels[l].begin(), b.levels[l].end());
      if (out.skirt_depth > 0.0f) {
        const size_t before = out.indices.size();
        append_skirt(mesh, b.levels[l], down, lowered, out.indices);
        level.skirt_count = uint32_t(out.indices.size() - before);
      }
      level.index_count = uint32_t(out.indices.size()) - level.first_index;
    }
    if (out.skirt_depth > 0.0f) {  // the box holds the skirts, whichever way the field faces
      const scene::Bounds surface = b.chunk.bounds;
      b.chunk.bounds.add(surface.min + down * out.skirt_depth);
      b.chunk.bounds.add(surface.max + down * out.skirt_depth);
    }
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
    const float distance = distance_to_box(wb, camera_pos);
    const uint32_t l = choose_level(chunk, world_scale, distance, pixels_per_unit, max_error_px);
    out.push_back({chunk.levels[l].first_index, chunk.levels[l].index_count, l, distance});
  }
}

float distance_to_box(const scene::Bounds& box, const glm::vec3& p) {
  const glm::vec3 d = glm::max(glm::max(box.min - p, p - box.max), glm::vec3(0.0f));
  return glm::length(d);
}

}  // namespace cumulo::render
