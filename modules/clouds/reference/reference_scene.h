#pragma once
// What the path-traced reference (reference_tracer.h) sees besides the clouds, built on the CPU from a
// frame snapshot: the terrain as a heightfield (the level's meshes rasterized from above: the highest
// surface per texel and its albedo) and the sky as a latitude-longitude table of the atmosphere's radiance
// (engine/render/atmosphere: the same model the real-time sky's LUTs integrate), plus the ocean plane.
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
};
// Every triangle of every model draw (its world transform and mesh instances applied), rasterized at
// texel centres into a square grid over the models' xz bounds. Empty without triangles.
TerrainHeightfield rasterize_heightfield(const std::vector<cumulo::render::ModelDraw>& models, uint32_t resolution = 512);

// Radiance (renderer units) arriving from direction (cos(e) cos(a), sin(e), cos(e) sin(a)) in texel
// (u, v) = ((a / 2 pi + 0.5) * width, (0.5 - e / pi) * height): row 0 is the zenith.
struct SkyEnvironment {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec4> texels;
};
// The atmosphere's sky (render::default_atmosphere(), its Mie density x snapshot.lighting.mie_scale) at the
// camera's altitude for the snapshot's sun, and the moon at night, as Atmosphere::lighting's sky.
SkyEnvironment sky_environment(const cumulo::render::FrameSnapshot& snapshot, uint32_t width = 128, uint32_t height = 64);

}  // namespace cumulo::clouds::render
