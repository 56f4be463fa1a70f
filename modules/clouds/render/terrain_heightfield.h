#pragma once
// The level's geometry seen from above as a heightfield: what the path-traced reference (reference_tracer.h) traces
// as terrain and what the Envelope method's baker (envelope_layer.h) sets orographic clouds on.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"

namespace cumulo::clouds::render {

// Texel (i, j) covers world x in origin.x + [i, i + 1) * size.x / resolution (z likewise with j); x: the
// highest surface's height (world y), yzw: its albedo (the material's base colour factor x the texture's
// mean, linear). Texels no triangle covers hold kNoTerrain.
struct TerrainHeightfield {
  static constexpr float kNoTerrain = -1.0e4f;
  uint32_t resolution = 0;
  glm::vec2 origin{0.0f}, size{1.0f};
  float min_height = 0.0f, max_height = 0.0f;  // over covered texels
  std::vector<glm::vec4> texels;               // resolution^2, row j = z
  bool empty() const { return texels.empty(); }
  // Bilinear over covered texels; `none` where no covered texel is near.
  float height_at(float x, float z, float none = 0.0f) const;
};
// Every triangle of every model draw (its world transform and mesh instances applied), rasterized at
// texel centres into a square grid over the models' xz bounds. Empty without triangles.
TerrainHeightfield rasterize_heightfield(const std::vector<cumulo::render::ModelDraw>& models, uint32_t resolution = 512);
// The same over the square of `side` metres from world (x, z) = `origin` (triangles outside it are clipped).
TerrainHeightfield rasterize_heightfield(const std::vector<cumulo::render::ModelDraw>& models, uint32_t resolution,
                                         glm::vec2 origin, float side);

}  // namespace cumulo::clouds::render
