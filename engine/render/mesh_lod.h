#pragma once
// Chunks and levels of detail for large meshes (issue 23). A mesh of many triangles (the sample terrain:
// four meshes of 129 x 129 vertices) is cut into chunks of about `chunk_triangles` along its two widest axes,
// and each chunk gets a chain of simplified index lists (meshoptimizer's meshopt_simplify), each with the
// mesh-space error it introduces. A height field shades from a normal texture (height_field_normals.h), so a
// coarse level looks as the full one does; one that stands over x and z (a terrain) also simplifies its
// chunks' borders, with a skirt under every level's border to close the gaps between neighbours at different
// levels (at the mesh's own outer border too: a terrain's tiles are separate meshes). Any other mesh keeps its
// chunks' borders locked, so neighbours at other levels meet without cracks. The geometry pass culls
// chunks against the frustum and draws the coarsest level whose error projects under a pixel budget.
// Vertices are shared: a level is an index range into the mesh's one vertex buffer (and its skirt vertices).
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine/render/height_field_normals.h"
#include "engine/scene/camera.h"
#include "engine/scene/model.h"

namespace cumulo::render {

struct MeshLodLevel {
  uint32_t first_index = 0, index_count = 0;
  float error = 0.0f;  // how far (mesh space) the level may stray from the full chunk; 0 for level 0
  uint32_t skirt_count = 0;  // the last indices of the level: its skirt (a height field's), not its surface
};

struct MeshChunk {
  scene::Bounds bounds;              // mesh space, of the chunk's triangles
  std::vector<MeshLodLevel> levels;  // level 0 = the chunk's own triangles, then coarser
};

struct ChunkedMesh {
  std::vector<uint32_t> indices;  // every chunk's levels, one after another
  std::vector<MeshChunk> chunks;
  HeightFieldNormals normals;     // a chunked height field's shading normals (width 0 otherwise)
  // A chunked height field's borders simplify with the rest of each chunk, so neighbours at different levels
  // may not meet: every level hangs a skirt (a wall this deep) from its border, to these copies of its border
  // vertices (their indices follow the mesh's own vertices).
  float skirt_depth = 0.0f;
  std::vector<scene::Vertex> skirt_vertices;
};

// The engine's default pixel budget of a chunk's error (--lod-error): see frame_renderer.cpp.
inline constexpr float kDefaultLodErrorPx = 3.0f;

struct MeshLodSettings {
  uint32_t min_triangles = 8192;    // smaller meshes: one chunk of one level, drawn as before
  uint32_t chunk_triangles = 2048;  // about 32 x 32 quads of a grid
  uint32_t max_levels = 5;          // each about a quarter of the one before
  // A height (mesh space) whose contour line shows as an edge: where an opaque sea cuts a terrain. A height
  // field's level also counts how far it moves that line (a height error over a flat beach moves the coast
  // by that error over the slope); NAN: none.
  float contour = NAN;
};

ChunkedMesh build_mesh_lods(const scene::Mesh& mesh, const MeshLodSettings& settings = {});

// The coarsest level of `chunk` whose error, scaled to world units by `world_scale`, projects to at most
// `max_error_px` pixels at `distance` (world units from the camera), where `pixels_per_unit` is the size in
// pixels of one world unit seen at distance 1 (viewport height / (2 tan(fov_y / 2))). max_error_px <= 0: level 0.
uint32_t choose_level(const MeshChunk& chunk, float world_scale, float distance, float pixels_per_unit, float max_error_px);

// Distance from `point` to the box (0 inside it).
float distance_to_box(const scene::Bounds& box, const glm::vec3& point);

struct ChunkDraw {
  uint32_t first_index = 0, index_count = 0, level = 0;
  float distance = 0.0f;  // from the camera to the chunk's world box (front-to-back order)
};

// What to draw of a mesh placed at `world`: every chunk whose world box meets `frustum` (all of a one-chunk
// mesh: the caller culled the mesh), each at choose_level with the camera at `camera_pos`. Appends to `out`.
void select_chunk_draws(const std::vector<MeshChunk>& chunks, const glm::mat4& world, const scene::Frustum& frustum,
                        const glm::vec3& camera_pos, float pixels_per_unit, float max_error_px, std::vector<ChunkDraw>& out);

}  // namespace cumulo::render
