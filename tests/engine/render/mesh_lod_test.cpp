// engine/render/mesh_lod.h on a terrain-like grid: chunks partition the triangles, levels shrink, neighbours
// at any two levels meet within the skirts that hang from every level's border (a height field) or share the
// same border at every level (any other mesh), a level stays near its stated error (and moves a contour line
// no farther), and the per-frame choice culls chunks outside the view and coarsens with distance.
#include "engine/render/mesh_lod.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

namespace cumulo::render {
namespace {

// n x n vertices, `spacing` apart in x and z, gentle hills of `amplitude` (like the sample terrain).
scene::Mesh grid_mesh(int n, float spacing, float amplitude) {
  scene::Mesh m;
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      const float fx = float(x) * spacing, fz = float(z) * spacing;
      const float y = amplitude * (std::sin(fx * 0.011f) * std::cos(fz * 0.017f) + 0.3f * std::sin(fx * 0.05f + fz * 0.03f));
      m.vertices.push_back({{fx, y, fz}, {0, 1, 0}, {float(x) / float(n - 1), float(z) / float(n - 1)}});
      m.bounds.add(m.vertices.back().position);
    }
  for (int z = 0; z + 1 < n; ++z)
    for (int x = 0; x + 1 < n; ++x) {
      const uint32_t a = uint32_t(z * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  return m;
}

// A closed tube along z: no axis sees every triangle from one side, so it is no height field.
scene::Mesh tube_mesh() {
  scene::Mesh tube;
  const int around = 64, along = 160;
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const float a = 6.2831853f * float(i) / float(around);
      tube.vertices.push_back({{20.0f * std::cos(a), 20.0f * std::sin(a) + 0.3f * std::sin(0.2f * float(j)), 2.0f * float(j)},
                               {std::cos(a), std::sin(a), 0.0f}, {0.0f, 0.0f}});
      tube.bounds.add(tube.vertices.back().position);
    }
  for (int j = 0; j + 1 < along; ++j)
    for (int i = 0; i < around; ++i) {
      const uint32_t a = uint32_t(j * around + i), b = uint32_t(j * around + (i + 1) % around), c = a + uint32_t(around),
                     d = b + uint32_t(around);
      tube.indices.insert(tube.indices.end(), {a, c, b, b, c, d});
    }
  return tube;
}

using Tri = std::array<uint32_t, 3>;

// A level's surface: its triangles without the skirt that follows them.
MeshLodLevel surface(const MeshLodLevel& l) {
  MeshLodLevel s = l;
  s.index_count = l.index_count - l.skirt_count;
  s.skirt_count = 0;
  return s;
}

std::multiset<Tri> triangles(const std::vector<uint32_t>& idx, uint32_t first, uint32_t count) {
  std::multiset<Tri> out;
  for (uint32_t i = first; i < first + count; i += 3) {
    Tri t{idx[i], idx[i + 1], idx[i + 2]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // same winding, canonical start
    out.insert(t);
  }
  return out;
}

// Undirected edges used by exactly one triangle.
std::set<std::pair<uint32_t, uint32_t>> border(const std::vector<uint32_t>& idx, const MeshLodLevel& l) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (uint32_t i = l.first_index; i < l.first_index + l.index_count; i += 3)
    for (int e = 0; e < 3; ++e) {
      uint32_t a = idx[i + e], b = idx[i + (e + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::set<std::pair<uint32_t, uint32_t>> out;
  for (auto& [edge, n] : uses)
    if (n == 1) out.insert(edge);
  return out;
}

// Height of the level's surface above (x, z), by the triangle that holds it in the xz plane; NAN if none.
float surface_height(const scene::Mesh& m, const std::vector<uint32_t>& idx, const MeshLodLevel& l, float x, float z) {
  for (uint32_t i = l.first_index; i < l.first_index + l.index_count; i += 3) {
    const glm::vec3 a = m.vertices[idx[i]].position, b = m.vertices[idx[i + 1]].position, c = m.vertices[idx[i + 2]].position;
    const float det = (b.z - c.z) * (a.x - c.x) + (c.x - b.x) * (a.z - c.z);
    if (std::abs(det) < 1e-12f) continue;
    const float w0 = ((b.z - c.z) * (x - c.x) + (c.x - b.x) * (z - c.z)) / det;
    const float w1 = ((c.z - a.z) * (x - c.x) + (a.x - c.x) * (z - c.z)) / det;
    const float w2 = 1.0f - w0 - w1;
    if (w0 >= -1e-5f && w1 >= -1e-5f && w2 >= -1e-5f) return w0 * a.y + w1 * b.y + w2 * c.y;
  }
  return NAN;
}

TEST(MeshLod, ASmallMeshIsOneChunkOfOneLevelAsItWas) {
  const scene::Mesh m = grid_mesh(10, 4.0f, 5.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  ASSERT_EQ(c.chunks.size(), 1u);
  ASSERT_EQ(c.chunks[0].levels.size(), 1u);
  EXPECT_EQ(c.indices, m.indices);
}

TEST(MeshLod, ChunksPartitionTheTrianglesAndLevelsShrinkWithGrowingError) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);  // one of the sample terrain's four meshes
  const ChunkedMesh c = build_mesh_lods(m);
  ASSERT_EQ(c.chunks.size(), 16u);  // 32768 triangles in chunks of about 2048
  std::multiset<Tri> all;
  size_t deep = 0;
  for (const MeshChunk& ch : c.chunks) {
    ASSERT_FALSE(ch.levels.empty());
    EXPECT_EQ(ch.levels[0].error, 0.0f);
    const MeshLodLevel full = surface(ch.levels[0]);
    const auto t = triangles(c.indices, full.first_index, full.index_count);
    all.insert(t.begin(), t.end());
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      EXPECT_LT(surface(ch.levels[l]).index_count, surface(ch.levels[l - 1]).index_count);
      EXPECT_GE(ch.levels[l].error, ch.levels[l - 1].error);
      EXPECT_GT(ch.levels[l].error, 0.0f);
    }
    deep += ch.levels.size() >= 3;
  }
  EXPECT_EQ(all, triangles(m.indices, 0, uint32_t(m.indices.size())));
  EXPECT_GE(deep, 8u) << "most chunks have at least two coarser levels";
  // Its borders simplify too (skirts close the gaps): the coarsest levels are far below a locked border's
  // 128-odd triangles for a chunk of 32 x 32 quads.
  uint32_t coarsest = UINT32_MAX;
  for (const MeshChunk& ch : c.chunks) coarsest = std::min(coarsest, surface(ch.levels.back()).index_count / 3);
  EXPECT_LT(coarsest, 40u);
}

// Every level of a height field's chunk hangs a skirt from each border edge of its surface, skirt_depth straight
// down; two chunks that share a border, each at any of its levels, are nowhere farther apart along it than
// that depth, so the skirt of the higher one closes the gap.
TEST(MeshLod, AHeightFieldsNeighboursAtAnyLevelsMeetWithinTheSkirts) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  ASSERT_GT(c.skirt_depth, 0.0f);
  ASSERT_FALSE(c.skirt_vertices.empty());
  for (const MeshChunk& ch : c.chunks)
    for (const MeshLodLevel& l : ch.levels) {
      const auto edges = border(c.indices, surface(l));
      EXPECT_EQ(l.skirt_count, 6u * edges.size());
      // Walls: each skirt triangle has one or two of its corners below the surface.
      for (uint32_t i = l.first_index + l.index_count - l.skirt_count; i < l.first_index + l.index_count; i += 3) {
        int lowered = 0;
        for (int k = 0; k < 3; ++k) lowered += c.indices[i + k] >= m.vertices.size();
        EXPECT_TRUE(lowered == 1 || lowered == 2);
      }
    }
  // The skirt vertices lie skirt_depth below a surface vertex each.
  for (const scene::Vertex& v : c.skirt_vertices) {
    const glm::vec3 up = v.position + glm::vec3(0.0f, c.skirt_depth, 0.0f);
    const bool found = std::any_of(m.vertices.begin(), m.vertices.end(),
                                   [&](const scene::Vertex& w) { return glm::length(w.position - up) < 1e-3f; });
    EXPECT_TRUE(found) << v.position.x << ", " << v.position.z;
  }
  // Neighbours: chunks whose full-detail borders share an edge. Along it, every pair of their levels.
  size_t pairs = 0;
  float widest = 0.0f;
  for (size_t a = 0; a < c.chunks.size(); ++a)
    for (size_t b = a + 1; b < c.chunks.size(); ++b) {
      const auto ea = border(c.indices, surface(c.chunks[a].levels[0])), eb = border(c.indices, surface(c.chunks[b].levels[0]));
      std::vector<std::pair<uint32_t, uint32_t>> shared;
      std::set_intersection(ea.begin(), ea.end(), eb.begin(), eb.end(), std::back_inserter(shared));
      if (shared.empty()) continue;
      ++pairs;
      for (const MeshLodLevel& la : c.chunks[a].levels)
        for (const MeshLodLevel& lb : c.chunks[b].levels)
          for (const auto& [i, j] : shared)
            for (float t : {0.0f, 0.25f, 0.5f}) {
              const glm::vec3 p = glm::mix(m.vertices[i].position, m.vertices[j].position, t);
              const float ha = surface_height(m, c.indices, surface(la), p.x, p.z);
              const float hb = surface_height(m, c.indices, surface(lb), p.x, p.z);
              ASSERT_FALSE(std::isnan(ha) || std::isnan(hb)) << "a level's outline moved at " << p.x << ", " << p.z;
              widest = std::max(widest, std::abs(ha - hb));
            }
    }
  EXPECT_EQ(pairs, 24u);  // a 4 x 4 grid of chunks: 12 + 12 shared sides
  EXPECT_GT(widest, 0.0f) << "the borders never differ: nothing for the skirts to do";
  EXPECT_LE(widest, c.skirt_depth);
}

// Any other mesh keeps its chunks' borders locked: the same border at every level, and no skirts.
TEST(MeshLod, AChunksBorderIsTheSameAtEveryLevelWhenItIsNoHeightField) {
  const scene::Mesh tube = tube_mesh();
  const ChunkedMesh c = build_mesh_lods(tube);
  EXPECT_EQ(c.skirt_depth, 0.0f);
  EXPECT_TRUE(c.skirt_vertices.empty());
  EXPECT_EQ(c.normals.width, 0u);
  size_t coarser = 0;
  for (const MeshChunk& ch : c.chunks) {
    const auto level0 = border(c.indices, ch.levels[0]);
    for (size_t l = 1; l < ch.levels.size(); ++l, ++coarser) {
      EXPECT_EQ(ch.levels[l].skirt_count, 0u);
      EXPECT_EQ(border(c.indices, ch.levels[l]), level0) << "level " << l;
    }
  }
  EXPECT_GT(coarser, 0u);
}

TEST(MeshLod, ALevelStaysWithinItsStatedErrorOfTheFullSurface) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  for (size_t k : {size_t(0), size_t(5), size_t(15)}) {  // a corner, an inner and the far corner chunk
    const MeshChunk& ch = c.chunks[k];
    ASSERT_GE(ch.levels.size(), 3u);
    const MeshLodLevel full = surface(ch.levels[0]);
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      // Denser than the build measured: 15 points inside every full-detail triangle, its corners included.
      float worst = 0.0f;
      for (uint32_t i = full.first_index; i < full.first_index + full.index_count; i += 3) {
        const glm::vec3 a = m.vertices[c.indices[i]].position, b = m.vertices[c.indices[i + 1]].position,
                        d = m.vertices[c.indices[i + 2]].position;
        for (int s = 0; s <= 4; ++s)
          for (int t = 0; s + t <= 4; ++t) {
            const glm::vec3 p = a + (b - a) * (float(s) / 4.0f) + (d - a) * (float(t) / 4.0f);
            const float h = surface_height(m, c.indices, surface(ch.levels[l]), p.x, p.z);
            ASSERT_FALSE(std::isnan(h)) << "chunk " << k << " level " << l << " leaves a hole at " << p.x << ", " << p.z;
            worst = std::max(worst, std::abs(h - p.y));
          }
      }
      EXPECT_LE(worst, ch.levels[l].error) << "chunk " << k << " level " << l;
      EXPECT_GT(worst, 0.25f * ch.levels[l].error) << "the stated error is not far above the real one";
    }
  }
}

// A height field that stands upright (a wall: its heights along z) shades from its normal texture but keeps
// its chunks' borders locked: skirts would stick out sideways behind it.
TEST(MeshLod, AnUprightHeightFieldHasNormalsButNoSkirts) {
  scene::Mesh wall = grid_mesh(129, 8.0f, 60.0f);
  for (scene::Vertex& v : wall.vertices) std::swap(v.position.y, v.position.z);
  wall.bounds = {};
  for (const scene::Vertex& v : wall.vertices) wall.bounds.add(v.position);
  const ChunkedMesh c = build_mesh_lods(wall);
  EXPECT_GT(c.normals.width, 0u);
  EXPECT_EQ(c.skirt_depth, 0.0f);
  EXPECT_TRUE(c.skirt_vertices.empty());
  for (const MeshChunk& ch : c.chunks)
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      EXPECT_EQ(ch.levels[l].skirt_count, 0u);
      EXPECT_EQ(border(c.indices, ch.levels[l]), border(c.indices, ch.levels[0])) << "level " << l;
    }
}

// A coast: a gentle slope (1 in 20) through the contour height 0, with bumps. With the contour given, a level
// moves the coastline (where it crosses lines along x, to the nearest point of the full surface's line) no
// farther than its stated error; measured with only the heights' error, it moves it farther.
float worst_contour_shift_over_error(const ChunkedMesh& c, const scene::Mesh& m) {
  float worst = 0.0f;
  for (const MeshChunk& ch : c.chunks) {
    if (ch.bounds.min.y > 0.0f || ch.bounds.max.y < 0.0f) continue;  // no coast in it
    // The full surface's coastline: a segment across each triangle of level 0 that crosses 0.
    std::vector<std::pair<glm::vec2, glm::vec2>> coast;
    const MeshLodLevel full = surface(ch.levels[0]);
    for (uint32_t i = full.first_index; i < full.first_index + full.index_count; i += 3) {
      std::vector<glm::vec2> ends;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = m.vertices[c.indices[i + k]].position, q = m.vertices[c.indices[i + (k + 1) % 3]].position;
        if (p.y * q.y < 0.0f) {
          const glm::vec3 x = glm::mix(p, q, p.y / (p.y - q.y));
          ends.emplace_back(x.x, x.z);
        }
      }
      if (ends.size() == 2) coast.emplace_back(ends[0], ends[1]);
    }
    auto distance_to_coast = [&](glm::vec2 p) {
      float d = 1e30f;
      for (const auto& [a, b] : coast) {
        const glm::vec2 e = b - a;
        const float t = std::clamp(glm::dot(p - a, e) / std::max(glm::dot(e, e), 1e-12f), 0.0f, 1.0f);
        d = std::min(d, glm::length(p - (a + t * e)));
      }
      return d;
    };
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      const MeshLodLevel level = surface(ch.levels[l]);
      for (float z = ch.bounds.min.z + 3.0f; z < ch.bounds.max.z; z += 16.0f) {
        float prev_x = NAN, prev_h = NAN;
        for (float x = ch.bounds.min.x + 0.25f; x < ch.bounds.max.x; x += 0.5f) {
          const float h = surface_height(m, c.indices, level, x, z);
          if (prev_h * h < 0.0f && !coast.empty()) {  // the level's coastline, between two samples
            const float xc = prev_x + (x - prev_x) * prev_h / (prev_h - h);
            worst = std::max(worst, distance_to_coast({xc, z}) / ch.levels[l].error);
          }
          prev_x = x, prev_h = h;
        }
      }
    }
  }
  return worst;
}

TEST(MeshLod, ALevelMovesAContourNoFartherThanItsError) {
  const int n = 129;
  const float spacing = 8.0f;
  scene::Mesh m = grid_mesh(n, spacing, 4.0f);
  for (scene::Vertex& v : m.vertices) v.position.y += 0.05f * (v.position.x - 500.0f);
  for (int z = 0; z < n; ++z)  // the surface's normals, from central differences of the heights
    for (int x = 0; x < n; ++x) {
      auto y = [&](int i, int j) { return m.vertices[size_t(std::clamp(j, 0, n - 1) * n + std::clamp(i, 0, n - 1))].position.y; };
      const float dx = (y(x + 1, z) - y(x - 1, z)) / (float(std::min(x + 1, n - 1) - std::max(x - 1, 0)) * spacing);
      const float dz = (y(x, z + 1) - y(x, z - 1)) / (float(std::min(z + 1, n - 1) - std::max(z - 1, 0)) * spacing);
      m.vertices[size_t(z * n + x)].normal = glm::normalize(glm::vec3(-dx, 1.0f, -dz));
    }
  m.bounds = {};
  for (const scene::Vertex& v : m.vertices) m.bounds.add(v.position);
  MeshLodSettings coast;
  coast.contour = 0.0f;
  const float with = worst_contour_shift_over_error(build_mesh_lods(m, coast), m);
  const float without = worst_contour_shift_over_error(build_mesh_lods(m), m);
  EXPECT_GT(with, 0.0f) << "no level moved the coast at all";
  EXPECT_LE(with, 1.0f);
  EXPECT_GT(without, 1.0f) << "the heights' error alone already bounds the coast";
  std::printf("coast shift over stated error: %.2f with the contour, %.2f without\n", with, without);
}

TEST(MeshLod, MeshesThatAreNoHeightFieldOrHaveNoAreaStillPartitionAndKeepFullDetail) {
  // A closed tube (no axis sees every triangle from one side): the levels use meshoptimizer's estimate.
  const scene::Mesh tube = tube_mesh();
  const ChunkedMesh t = build_mesh_lods(tube);
  ASSERT_GT(t.chunks.size(), 1u);
  std::multiset<Tri> all;
  for (const MeshChunk& ch : t.chunks) {
    const auto tris = triangles(t.indices, ch.levels[0].first_index, ch.levels[0].index_count);
    all.insert(tris.begin(), tris.end());
    for (size_t l = 1; l < ch.levels.size(); ++l) EXPECT_GT(ch.levels[l].error, 0.0f);
  }
  EXPECT_EQ(all, triangles(tube.indices, 0, uint32_t(tube.indices.size())));
  // Every triangle on one point: no area, no box; one chunk at least, and its full detail as it was.
  scene::Mesh dot;
  dot.vertices.assign(3, scene::Vertex{{1.0f, 2.0f, 3.0f}, {0, 1, 0}, {0, 0}});
  for (int i = 0; i < 9000; ++i) dot.indices.insert(dot.indices.end(), {0u, 1u, 2u});
  const ChunkedMesh d = build_mesh_lods(dot);
  ASSERT_FALSE(d.chunks.empty());
  uint32_t drawn = 0;
  for (const MeshChunk& ch : d.chunks) drawn += ch.levels[0].index_count;
  EXPECT_EQ(drawn, dot.indices.size());
}

TEST(MeshLod, FarChunksTakeCoarserLevelsAndAZeroBudgetKeepsFullDetail) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  const MeshChunk& ch = c.chunks[0];
  const float ppu = 90.0f / std::tan(glm::radians(30.0f));  // 180 pixels high, 60 degrees
  uint32_t last = 0;
  for (float d : {1.0f, 100.0f, 1000.0f, 10000.0f, 100000.0f}) {
    const uint32_t l = choose_level(ch, 1.0f, d, ppu, 0.25f);
    EXPECT_GE(l, last) << d;
    last = l;
    EXPECT_EQ(choose_level(ch, 1.0f, d, ppu, 0.0f), 0u);
    if (l > 0) {
      EXPECT_LE(ch.levels[l].error * ppu / d, 0.25f);  // the chosen level's error fits the budget
    }
  }
  EXPECT_EQ(choose_level(ch, 1.0f, 1.0f, ppu, 0.25f), 0u);
  EXPECT_EQ(last, ch.levels.size() - 1);
  // A placement that scales the mesh up scales its error with it.
  EXPECT_LE(choose_level(ch, 10.0f, 1000.0f, ppu, 0.25f), choose_level(ch, 1.0f, 1000.0f, ppu, 0.25f));
}

TEST(MeshLod, ChunksOutsideTheViewAreNotDrawn) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);  // 1024 x 1024 m
  const ChunkedMesh c = build_mesh_lods(m);
  const glm::mat4 proj = glm::perspective(glm::radians(60.0f), 16.0f / 9.0f, 1.0f, 10000.0f);
  const float ppu = 90.0f / std::tan(glm::radians(30.0f));
  auto draws = [&](glm::vec3 eye, glm::vec3 at, float max_error_px = 0.25f) {
    std::vector<ChunkDraw> out;
    select_chunk_draws(c.chunks, glm::mat4(1.0f), scene::Frustum::from(proj * glm::lookAt(eye, at, {0, 1, 0})), eye, ppu,
                       max_error_px, out);
    return out;
  };
  // High above the middle looking down: every chunk; from a corner looking out, away from the mesh: none.
  EXPECT_EQ(draws({512, 3000, 512}, {512, 0, 513}).size(), c.chunks.size());
  EXPECT_TRUE(draws({-10, 50, -10}, {-1000, 50, -1000}).empty());
  // From a corner looking along one edge: some, not all.
  const auto edge = draws({-10, 100, -10}, {1100, 0, -10});
  EXPECT_GT(edge.size(), 0u);
  EXPECT_LT(edge.size(), c.chunks.size());
  // Seen from a corner over the mesh, far chunks take coarser levels than the near one.
  const auto low = draws({0, 200, 0}, {1024, 0, 1024}, 2.0f);
  ASSERT_FALSE(low.empty());
  uint32_t coarsest = 0;
  for (const ChunkDraw& d : low) coarsest = std::max(coarsest, d.level);
  EXPECT_GT(coarsest, low.front().level);  // chunk 0, under the camera
}

}  // namespace
}  // namespace cumulo::render
