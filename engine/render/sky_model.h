#pragma once
// The sky of the engine: the SceneLighting of a frame (sky zenith and horizon colours, the sun or moon at
// the ground, ambient, fog) from the physically based atmosphere (atmosphere/atmosphere.h, the preset
// content/atmosphere/earth.json, loaded once). Pure CPU math, tested alone. A module may replace the result
// in its extract().
#include <glm/glm.hpp>

#include "engine/render/frame_snapshot.h"
#include "shaders/shared/frame_params.h"

namespace cumulo::render {

// The renderer's units: scene::SunLight::radiance (about 1 at noon for a white sun of illuminance 1)
// times this is what the shaders use, so exposure 1 with ACES shows a noon scene unclipped.
inline constexpr float kSunRadianceScale = 3.0f;

class Atmosphere;
// The process's atmosphere (the Earth preset), built on first use (~50 ms: its tables).
const Atmosphere& default_atmosphere();
SceneLighting sky_lighting(const scene::SunLight& sun, float camera_altitude_m = 0.0f);

// Toward the key light of the frame: lighting.light_direction when set (the moon at night), else the sun.
glm::vec3 key_light_direction(const FrameSnapshot& snapshot);

// FrameParams of the engine passes for a snapshot (camera matrices, sun, snapshot.lighting, viewport).
shared::FrameParams make_frame_params(const FrameSnapshot& snapshot, float exposure = 1.0f);

}  // namespace cumulo::render
