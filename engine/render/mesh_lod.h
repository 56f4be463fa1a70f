#pragma once
// Chunks and levels of detail for large meshes (issue 23). A mesh of many triangles (the sample terrain:
// four meshes of 129 x 129 vertices) is cut into chunks of about `chunk_triangles` along its two widest axes,
// and each chunk gets a chain of simplified index lists (meshoptimizer's meshopt_simplify, the chunk's border
// locked so neighbours at other levels meet without cracks), each with the mesh-space error it introduces.
// The geometry pass culls chunks against the frustum and draws the coarsest level whose error projects under
// a pixel budget. Vertices are shared: a level is an index range into the mesh's one vertex buffer.
#include <cstdint>
#include <vector>

#include "engine/scene/camera.h"
#include "engine/scene/model.h"

namespace cumulo::render {

struct MeshLodLevel {
  uint32_t first_index = 0, index_count = 0;
  float error = 0.0f;  // how far (mesh space) the level may stray from the full chunk; 0 for level 0
};

struct MeshChunk {
  scene::Bounds bounds;              // mesh space, of the chunk's triangles
  std::vector<MeshLodLevel> levels;  // level 0 = the chunk's own triangles, then coarser
};

struct ChunkedMesh {
  std::vector<uint32_t> indices;  // every chunk's levels, one after another
  std::vector<MeshChunk> chunks;
};

struct MeshLodSettings {
  uint32_t min_triangles = 8192;    // smaller meshes: one chunk of one level, drawn as before
  uint32_t chunk_triangles = 2048;  // about 32 x 32 quads of a grid
  uint32_t max_levels = 5;          // each about a quarter of the one before
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
};

// What to draw of a mesh placed at `world`: every chunk whose world box meets `frustum` (all of a one-chunk
// mesh: the caller culled the mesh), each at choose_level with the camera at `camera_pos`. Appends to `out`.
void select_chunk_draws(const std::vector<MeshChunk>& chunks, const glm::mat4& world, const scene::Frustum& frustum,
                        const glm::vec3& camera_pos, float pixels_per_unit, float max_error_px, std::vector<ChunkDraw>& out);

}  // namespace cumulo::render
