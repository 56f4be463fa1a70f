#pragma once
// Sampled signed distance grids that recipe edits can place like primitives: a voxelized glTF mesh
// (the talk's "Meshes" source for Atlas) or an imported volume (an .nvdf written by `cumulo bake` or
// `cumulo import`: the "Voxels" source, e.g. a simulated cloud from a library, as SmogVox's
// frankencloudscapes reused simulated clouds).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/bake/recipe.h"

namespace cumulo::clouds::bake {

class GridSdf {
 public:
  glm::uvec3 dims{0};
  glm::vec3 origin{0.0f};  // local position of sample (0, 0, 0)
  float spacing = 1.0f;
  std::vector<float> values;  // signed distance in local units, x fastest

  float at(uint32_t x, uint32_t y, uint32_t z) const { return values[x + size_t(dims.x) * (y + size_t(dims.y) * z)]; }
  // Trilinear inside the grid; outside, the distance to the grid box plus the clamped sample (the
  // grids carry a positive margin, so this stays a continuation of the field).
  float sample(glm::vec3 p) const;
};

Aabb grid_bounds(const GridSdf& g);

// Signed distance of a closed triangle mesh (positions, 3 per triangle) sampled every `spacing` units
// over its bounds plus a margin: exact point-triangle distances within a few samples of the surface,
// the exact EDT of the inside/outside voxels beyond; inside/outside by ray parity along x (majority
// of three rays per row, so a ray grazing an edge does not flip a row).
std::shared_ptr<GridSdf> voxelize_triangles(const std::vector<glm::vec3>& triangles, float spacing);

// Loads a glTF (every mesh instance of its default scene, in model space) and voxelizes it;
// resolution 0 picks 1/64 of the largest extent. Needs the engine's glTF loader (cumulo_scene).
std::shared_ptr<GridSdf> voxelize_gltf_file(const std::filesystem::path& path, float resolution);

// Loads an .nvdf: its "sdf" channel (metres) when it has one; otherwise its dimensional profile,
// turned into a distance (the surface is where profile = iso) by the exact EDT. Local space is the
// volume's own box.
std::shared_ptr<GridSdf> load_volume_sdf(const std::filesystem::path& path, float iso);

}  // namespace cumulo::clouds::bake
