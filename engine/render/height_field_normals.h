#pragma once
// A height-field mesh's shading normals as a texture over the plane it stands on, so that every level of
// detail (mesh_lod.h) shades as the full mesh does. A coarse level's larger triangles would otherwise
// interpolate the kept vertices' normals across the vertices it dropped: a lit flank turns flat, and the
// shading pops where the level changes, which is what held the terrain's error threshold at a quarter pixel.
// The normals are in mesh space, not tangent space, so they do not depend on which triangles are drawn.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/scene/model.h"

namespace cumulo::render {

struct HeightFieldNormals {
  uint32_t width = 0, height = 0;    // 0: no texture (not a height field)
  std::vector<uint8_t> rgba;         // the mesh-space normal n as (n * 0.5 + 0.5) * 255, alpha 255; row-major
  glm::vec4 plane_u{0.0f}, plane_v{0.0f};  // a mesh-space point p's texture coordinate: dot(vec4(p, 1), plane_*)
};

// The normals of `triangles` (indices into mesh.vertices, a height field along axis `h` over axes `u`, `v`):
// each texel holds the triangle under it's interpolated vertex normal, the texel centres at the box's edges
// (neighbouring meshes of one terrain sample the same normals on their shared border). About two texels
// per vertex spacing, at most `max_size` along an axis.
HeightFieldNormals build_height_field_normals(const scene::Mesh& mesh, const std::vector<uint32_t>& triangles, int u,
                                              int v, int h, uint32_t max_size = 1024);

}  // namespace cumulo::render
