#pragma once
// The extraction of the clouds' frame (cloud_frame.h): once per rendered frame the world's Cloudscapes,
// live lightning and the weather drawn (weather::weather_drawn) become one CloudFrame in the snapshot's
// extensions, and the lightning's light on the ground and the weather's haze go into snapshot.lighting.
#include "engine/ecs/world.h"
#include "engine/render/frame_snapshot.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds {

// What a weather state changes in a frame: the voxel clouds' lighting constants (CloudWeatherLighting),
// every instance's density (x voxel_density), coverage (which placed clouds exist: the recipe's per-edit
// "coverage" threshold, CLOUD_COVERAGE_RAMP in shaders/shared/cloud_params.h) and wind (the weather's
// replaces the Cloudscape's), and the 2.5D sky's parameters. The other keys (cloud map, lightning, rain)
// are the sky's and gameplay's.
void apply_weather(const weather::WeatherState& w, CloudFrame& frame);
// The Mie (aerosol) density multiplier of a weather state's haze (0..1): the atmosphere's Mie density
// (SceneLighting::mie_scale) and the height fog, x 1 at the sample's 0.1 (the preset's clear air), 0.5 at
// 0.05, 4 at 0.4.
float haze_mie_scale(float haze);

// Sets the CloudFrame extension of `snapshot` (Cloudscapes added after the level loaded are left out until
// their asset is resolved).
void extract_cloud_frame(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot);

}  // namespace cumulo::clouds
