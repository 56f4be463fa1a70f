#pragma once
// The stand-in sky of the engine (the cloud module brings the real atmosphere): colours for the sky
// gradient, the ambient term and the fog, chosen from the sun's elevation. Pure CPU math, tested alone.
#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"
#include "shaders/shared/frame_params.h"

namespace cumulo::render {

struct SkyColors {
  glm::vec3 zenith{0.0f}, horizon{0.0f}, ground{0.0f};
  glm::vec3 sun_radiance{0.0f};  // sun colour x intensity as the shaders use it
  float ambient = 0.0f;          // scale of the hemispheric ambient term
  float fog_density = 0.0f;      // 1/m at sea level
  float fog_falloff = 0.0f;      // 1/m (exponential height falloff)
};

SkyColors sky_colors(const SunLight& sun);

// FrameParams of the engine passes for a snapshot (camera matrices, sun, sky, viewport).
shared::FrameParams make_frame_params(const FrameSnapshot& snapshot, float exposure = 1.0f);

}  // namespace cumulo::render
