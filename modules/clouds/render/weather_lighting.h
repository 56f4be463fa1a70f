#pragma once
// What a weather state (modules/clouds/weather) changes in the voxel-cloud renderer's frame: the
// lighting constants, the sky ambient, every instance's density multiplier, coverage and wind.
//   lighting.absorption       -> CloudSettings::extinction (1/m per unit density)
//   lighting.phase.forward    -> hg_forward x (1 - lighting.silver.spread)   (spread widens the forward lobe)
//   lighting.phase.backward   -> hg_backward
//   lighting.silver.intensity -> hg_forward_weight (the silver lining's share of the dual-lobe phase)
//   lighting.ambient          -> ambient colour multiplier
//   voxel_density             -> each instance's density x this
//   coverage                  -> each instance's coverage: which placed clouds exist (the recipe's per-edit
//                                "coverage" threshold; CLOUD_COVERAGE_RAMP in shaders/shared/cloud_params.h)
//   wind                      -> each instance's wind (the weather's wind replaces the Cloudscape's)
//   haze                      -> haze_mie_scale: the atmosphere's Mie density (SceneLighting::mie_scale) and the
//                                height fog, x 1 at the sample's 0.1 (the preset's clear air), 0.5 at 0.05, 4 at 0.4
// The other keys (cloud map, lightning, rain) are the 2.5D sky's and gameplay's (coverage is the sky's too).
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds::render {

void apply_weather(const weather::WeatherState& w, CloudFrameInputs& in);
// The Mie (aerosol) density multiplier of a weather state's haze (0..1).
float haze_mie_scale(float haze);

}  // namespace cumulo::clouds::render
