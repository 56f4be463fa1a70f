#pragma once
// The Envelope method's bake (issue 24): an OrographicClouds component and the terrain -> EnvelopeMaps
// (envelope_maps.h), and the CPU mirror of the talk's dimensional profile (shaders/clouds/envelope_density.glsl).
//
//   EnvelopeMaps m = bake_envelope_maps(spec, [&](float x, float z) { return terrain.height(x, z); });
//   float p = sample_envelope(m, {x, y, z}).profile;
//
// Steps: the terrain sampled at the texel centres; the painted maps then the rules, united per texel; the ceiling;
// a Euclidean distance transform (Felzenszwalb & Huttenlocher 2012, exact on texel centres) for the dilation of the
// heights into empty texels and for edge_m; the 3x3 conservative top and bottom; the cone ratios and the distance
// step (envelope_steps.h). Resolution 256 bakes in 0.1 to 0.2 s on one core (Release), 1024 in about 4 s.
#include <functional>

#include <glm/glm.hpp>

#include "modules/clouds/envelope/envelope_maps.h"
#include "modules/clouds/envelope/orographic_clouds.h"

namespace cumulo::clouds::envelope {

using HeightField = std::function<float(float x, float z)>;

inline constexpr float kCeilingGapM = 20.0f;  // between the envelope's top and the voxel clouds' base above it

// terrain_height: the terrain's world y (sea level 0 where there is none); called from this thread only.
// ceiling: optional, the world y the envelope's top must stay below (the voxel clouds' base in that column; +inf
// where none): the top is clamped to ceiling - kCeilingGapM, and a texel left thinner than kMinThicknessM holds no
// cloud. progress: optional, 0..1, from this thread.
// Throws cumulo::Error (naming the file and JSON path) where painted maps cannot be read; a spec that was not
// resolved (resolve_orographic_clouds) has its maps read relative to spec.level_dir.
EnvelopeMaps bake_envelope_maps(const OrographicClouds& spec, const HeightField& terrain_height,
                                const HeightField& ceiling = {}, const std::function<void(float)>& progress = {});

// The talk's Envelope Method profile: height_fraction = remap(y, bottom, top, 0, 1); top_gradient = pow(1 - hf, 1.5);
// bottom_gradient = pow(hf, 2); edge_gradient = saturate(edge_m_here / edge_width_m) (the talk's
// remap(sample_height, 0, 35, 1, 0), reading sample_height as the distance still to go to a band edge_width_m inside
// the side: the gradient "increases in value going in from the sides"); profile = bottom * top * edge / kProfilePeak
// * saturate(coverage), 0 outside (bottom, top) or where coverage <= 0.
inline constexpr float kProfilePeak = 0.0916133417f;  // (3/7)^1.5 (4/7)^2: the product's maximum, at hf = 4/7
float envelope_profile(float y, float bottom, float top, float edge_m_here, float edge_width_m, float coverage);

struct EnvelopeSample {
  glm::vec4 shape{0.0f};  // bilinear: bottom, top, coverage, detail type
  float edge_m = 0.0f;    // bilinear
  float height_fraction = 0.0f;
  float edge_gradient = 0.0f;
  float profile = 0.0f;  // envelope_profile (before the noise's up-rez); 0 outside the map's square
};
// Bilinear like the GPU's sampler (clamped to the edge texels' centres) inside the map's square; nothing outside it.
EnvelopeSample sample_envelope(const EnvelopeMaps& maps, glm::vec3 world);

}  // namespace cumulo::clouds::envelope
