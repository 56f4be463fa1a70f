#pragma once
// The stand-in sky of the engine (until the atmosphere issue brings a physically based one): the
// SceneLighting of a frame (sky gradient colours, sun radiance at the ground, ambient, fog) chosen from
// the sun's elevation. Pure CPU math, tested alone. A module may replace the result in its extract().
#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"
#include "shaders/shared/frame_params.h"

namespace cumulo::render {

// The renderer's units: scene::SunLight::radiance (about 1 at noon for a white sun of illuminance 1)
// times this is what the shaders use, so exposure 1 with ACES shows a noon scene unclipped.
inline constexpr float kSunRadianceScale = 3.0f;

SceneLighting stand_in_lighting(const scene::SunLight& sun);

// FrameParams of the engine passes for a snapshot (camera matrices, sun, snapshot.lighting, viewport).
shared::FrameParams make_frame_params(const FrameSnapshot& snapshot, float exposure = 1.0f);

}  // namespace cumulo::render
