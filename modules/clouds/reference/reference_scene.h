#pragma once
// What the path-traced reference (reference_tracer.h) sees besides the clouds, built on the CPU from a
// frame snapshot: the terrain as a heightfield (the level's meshes rasterized from above: the highest
// surface per texel and its albedo) and the sky as a latitude-longitude table of the atmosphere's radiance
// (engine/render/atmosphere: the same model the real-time sky's LUTs integrate), plus the ocean plane.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"
#include "modules/clouds/render/terrain_heightfield.h"

namespace cumulo::clouds::render {

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
