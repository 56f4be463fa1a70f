#pragma once
// Evaluation of a recipe's edit list: the composed signed distance plus the per-voxel modeling
// attributes (detail type, density scale, coverage threshold) blended with the same soft-min weights, on a
// bake grid.
//
// Index:  BakeGrid  EvalSample  evaluate_point  compose  ParticleBins  erosion_noise
//
// Bounds culling: every edit has a box (its shape, transformed and sheared, grown by its blend radius
// and a band of a few voxels); a voxel evaluates only the edits whose box holds it. Rows of voxels
// along x first collect the edits that cross them, so a voxel never looks at far edits. Skipping an
// edit outside its box is exact where it matters: the sign everywhere, and the value within the band
// of the surface (far values are replaced by the exact distance transform later).
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/bake/recipe.h"

namespace cumulo {
class Progress;
}

namespace cumulo::clouds::bake {

// The value of "no cloud anywhere near": larger than any distance the field stores.
inline constexpr float kFarDistance = 1.0e5f;

// Voxel (i, j, k) has its centre at origin + (i, j, k) * spacing; world axes (x, y up, z).
struct BakeGrid {
  glm::uvec3 dims{0};
  glm::vec3 origin{0.0f};   // centre of voxel (0, 0, 0)
  glm::vec3 spacing{8.0f};  // metres per voxel along x, y, z
  size_t count() const { return size_t(dims.x) * dims.y * dims.z; }
  size_t index(uint32_t x, uint32_t y, uint32_t z) const { return x + size_t(dims.x) * (y + size_t(dims.y) * z); }
  glm::vec3 position(uint32_t x, uint32_t y, uint32_t z) const { return origin + glm::vec3(x, y, z) * spacing; }
  glm::vec3 bounds_min() const { return origin - 0.5f * spacing; }
  glm::vec3 bounds_max() const { return origin + (glm::vec3(dims) - 0.5f) * spacing; }
};

// The grid for a recipe: its bounds at its voxel size (dims = round(extent / voxel)), or, when
// `dims_override` is non-zero, those dims over the same bounds.
BakeGrid make_grid(const Recipe& recipe, glm::uvec3 dims_override = glm::uvec3(0));

struct EvalSample {
  float d = kFarDistance;  // metres, negative inside
  float detail_type = 0.0f;
  float density_scale = 0.0f;
  float profile_depth = 96.0f;  // metres (grown clouds: from the cloud's local thickness)
  float coverage = 0.0f;        // coverage threshold 0..1 (recipe.h Edit::coverage)
};

// The composed field at one world point (no row culling; edits are still skipped outside their box).
EvalSample evaluate_point(const Recipe& recipe, glm::vec3 p);

struct Composed {
  std::vector<float> sdf;  // metres
  std::vector<float> detail_type;
  std::vector<float> density_scale;
  std::vector<float> coverage;  // coverage threshold per voxel
  std::vector<float> profile_depth;
  uint64_t edit_evaluations = 0;  // how many (voxel, edit) pairs were evaluated (culling statistic)
};

// Evaluates every voxel of `grid` on all cores. `progress` (optional) advances by one per row.
Composed compose(const Recipe& recipe, const BakeGrid& grid, Progress* progress = nullptr);

// Spatial hash of a particle edit's spheres (cell = 2 * largest radius + blend): a point only looks
// at the 27 cells around it.
struct ParticleBins {
  float cell = 1.0f;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
};
std::shared_ptr<const ParticleBins> build_particle_bins(const std::vector<Particle>& particles, float blend);

// Erosion noise in [0, 1]: the noise module's seeded Perlin fBm at `frequency` cycles per metre.
float erosion_noise(glm::vec3 p, float frequency, int octaves, uint32_t seed);

}  // namespace cumulo::clouds::bake
