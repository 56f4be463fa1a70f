// engine/render/mesh_lod.h on a terrain-like grid: chunks partition the triangles, levels shrink, a chunk's
// border is the same at every level (neighbours at other levels meet without cracks), a level stays near its
// stated error, and the per-frame choice culls chunks outside the view and coarsens with distance.
#include "engine/render/mesh_lod.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
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

using Tri = std::array<uint32_t, 3>;

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
    const auto t = triangles(c.indices, ch.levels[0].first_index, ch.levels[0].index_count);
    all.insert(t.begin(), t.end());
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      EXPECT_LT(ch.levels[l].index_count, ch.levels[l - 1].index_count);
      EXPECT_GE(ch.levels[l].error, ch.levels[l - 1].error);
      EXPECT_GT(ch.levels[l].error, 0.0f);
    }
    deep += ch.levels.size() >= 3;
  }
  EXPECT_EQ(all, triangles(m.indices, 0, uint32_t(m.indices.size())));
  EXPECT_GE(deep, 8u) << "most chunks have at least two coarser levels";
}

TEST(MeshLod, AChunksBorderIsTheSameAtEveryLevel) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  for (const MeshChunk& ch : c.chunks) {
    const auto level0 = border(c.indices, ch.levels[0]);
    for (size_t l = 1; l < ch.levels.size(); ++l) EXPECT_EQ(border(c.indices, ch.levels[l]), level0) << "level " << l;
  }
}

TEST(MeshLod, ALevelStaysWithinItsStatedErrorOfTheFullSurface) {
  const scene::Mesh m = grid_mesh(129, 8.0f, 60.0f);
  const ChunkedMesh c = build_mesh_lods(m);
  for (size_t k : {size_t(0), size_t(5), size_t(15)}) {  // a corner, an inner and the far corner chunk
    const MeshChunk& ch = c.chunks[k];
    ASSERT_GE(ch.levels.size(), 3u);
    const MeshLodLevel& full = ch.levels[0];
    for (size_t l = 1; l < ch.levels.size(); ++l) {
      // Denser than the build measured: 15 points inside every full-detail triangle, its corners included.
      float worst = 0.0f;
      for (uint32_t i = full.first_index; i < full.first_index + full.index_count; i += 3) {
        const glm::vec3 a = m.vertices[c.indices[i]].position, b = m.vertices[c.indices[i + 1]].position,
                        d = m.vertices[c.indices[i + 2]].position;
        for (int s = 0; s <= 4; ++s)
          for (int t = 0; s + t <= 4; ++t) {
            const glm::vec3 p = a + (b - a) * (float(s) / 4.0f) + (d - a) * (float(t) / 4.0f);
            const float h = surface_height(m, c.indices, ch.levels[l], p.x, p.z);
            ASSERT_FALSE(std::isnan(h)) << "chunk " << k << " level " << l << " leaves a hole at " << p.x << ", " << p.z;
            worst = std::max(worst, std::abs(h - p.y));
          }
      }
      EXPECT_LE(worst, ch.levels[l].error) << "chunk " << k << " level " << l;
      EXPECT_GT(worst, 0.25f * ch.levels[l].error) << "the stated error is not far above the real one";
    }
  }
}

TEST(MeshLod, MeshesThatAreNoHeightFieldOrHaveNoAreaStillPartitionAndKeepFullDetail) {
  // A closed tube (no axis sees every triangle from one side): the levels use meshoptimizer's estimate.
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
