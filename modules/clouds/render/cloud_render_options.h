#pragma once
// What the clouds' real-time frame draws and how: the renderer's part of the clouds' `cumulo run` flags
// (parsed once, options/cloud_options.h), which `cumulo bench` and `cumulo fidelity` also set between
// frames. Plain data.
#include <cstdint>
#include <optional>

#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::clouds::render {

struct CloudRenderOptions {
  bool enabled = true;  // --clouds
  CloudDebugView debug = CloudDebugView::None;
  std::optional<CloudFormatSet> formats;  // empty: default_format_set(device)
  CloudAblation ablation = CloudAblation::Full;
  bool temporal = true;
  uint32_t reprojection_block = 0;  // CloudSettings::reprojection_block (0: by budget mode)
  uint32_t near_reprojection_block = 4;  // CloudSettings::near_reprojection_block (--cloud-near-reprojection)
  bool talk_jitter = false;  // --cloud-jitter talk: animated within 250 m only (CloudSettings::animated_jitter_distance_m)
  // --cloud-light-grid: true the talk's 256x256x32 on every device, false the device's (CloudResourcesDesc::for_device);
  // none: the device's, except in `cumulo fidelity` (the talk's).
  std::optional<bool> talk_light_grid;
  uint32_t light_grid_samples = 0;  // CloudResourcesDesc::light_grid_sweep_samples (0: the device's)
  CloudLightGridMethod light_grid_method = CloudLightGridMethod::Sweep;
  bool light_sample_noise_mean = true;  // CloudSettings::light_sample_noise_mean
  CloudLights lights = CloudLights::All;  // --cloud-lights: CloudSettings::lights
  bool light_grid_always_update = false;  // CloudSettings::light_grid_always_update (cumulo bench)
  bool shadows = true;  // --cloud-shadows: the clouds' shadow on the terrain and the ocean
  std::optional<bool> sky;  // --cloud-sky on|off; none (auto): on when the level has a WeatherScheduler
  bool sky_occlusion = true;  // --cloud-sky-occlusion: the 2.5D sky is not marched where the voxel clouds hide it
  std::optional<bool> envelope;  // --envelope on|off; none (auto): on when the level has OrographicClouds
  bool envelope_cone_stepping = true;  // --envelope-stepping cone|fixed
  uint32_t envelope_block = 0;  // --envelope-reprojection: EnvelopeMarchSettings::far_block (0: by device)
  bool light_shafts = true;  // --cloud-light-shafts
  bool rain = true;          // --cloud-rain
  bool terrain_shadow = true;  // --cloud-terrain-shadow: the terrain's shadow on the clouds
  uint32_t effects = CLOUD_EFFECTS_ALL;  // --cloud-effects-off: CLOUD_EFFECT_* bits in effect
  CloudLightingPreset lighting = CloudLightingPreset::Slab;  // --cloud-lighting talk|tuned|diffusion|slab|solve
  // The preset's constants overridden by flags (< 0 or empty: the preset's).
  float ms_strength = -1.0f;            // --cloud-ms-strength
  float ambient_occlusion = -1.0f;      // --cloud-ambient-occlusion
  float ms_attenuation_inside = -1.0f;  // --cloud-ms-attenuation-inside
  float ms_other_clouds = -1.0f;        // --cloud-ms-other-clouds
  float ms_enclosed = -1.0f;            // --cloud-ms-enclosed
  float ground_albedo = -1.0f;          // --cloud-ground-albedo
  float ms_anisotropy = -1.0f;          // --cloud-ms-anisotropy
  float ms_incidence = -1.0f;           // --cloud-ms-incidence
  float ms_cavity = -1.0f;              // --cloud-ms-cavity
  float sky_side = -1.0f;               // --cloud-sky-side
  float ms_forward = -1.0f;             // --cloud-ms-forward
  float envelope_ms_diffused = -1.0f;   // --envelope-ms-diffused
  float envelope_eccentricity = -1.0f;  // --envelope-octave-eccentricity
  std::optional<bool> envelope_light_erosion;  // --envelope-light-erosion
  float light_sample_m = -1.0f;         // --cloud-light-sample-m
  int light_samples = -1;               // --cloud-light-samples
  float light_sample_growth = -1.0f;    // --cloud-light-sample-growth
  float edge_depth = -1.0f;             // --cloud-edge-depth
  std::optional<bool> instance_shadows;  // --cloud-instance-shadows
  float ms_lateral = -1.0f;             // --cloud-ms-lateral
  int ms_solve_iterations = -1;         // --cloud-ms-solve-iterations
  int ms_solve_local = -1;              // --cloud-ms-solve-local
  float ms_solve_omega = -1.0f;         // --cloud-ms-solve-omega
  float ms_solve_weight = -1.0f;        // --cloud-ms-solve-weight
  float ms_solve_strength = -1.0f;      // --cloud-ms-solve-strength
  float step_growth = -1.0f;     // --cloud-step-growth (< 0: the setting's default)
  float split_distance_m = -1.0f;  // --cloud-split-distance (< 0: by device, split_distance_for_device)
  std::optional<bool> sky_mean;         // --cloud-sky-mean
  std::optional<bool> sky_hue;          // --cloud-sky-hue
  // cumulo fidelity: draw only what the path-traced reference traces (the voxel clouds): no 2.5D sky,
  // light shafts, rain or bolt channels.
  bool reference_comparable = false;
  int noise_size = 128;
  // --cloud-growth-steps-per-frame: a growing cloud (CloudGrowth) takes at most this many simulation steps a frame
  // toward its target (0: the clouds do not grow). Lavapipe: ~12 ms a step on 16x12x16 cells, 255-350 ms on 64x32x64.
  int growth_steps_per_frame = 1;
  // --cloud-growth-spread: the images (and the light grid) in the frame after the steps (CloudGrowthRuntime::plan).
  bool growth_spread = true;
  // --cloud-growth-update-frames: with the spread, the images' update over this many frames (the distance field's
  // and attributes' passes, then the images alone), no step meanwhile; 0: by device (growth_update_frames_for_device).
  int growth_update_frames = 0;
  // --cloud-growth-light-sweep: a grown cloud's new images are swept into its light grid over the next cycle of
  // frames (the sweep method's, from the level nearest the light) instead of a rebuild in the update's last frame.
  // Off by default: a lighting that changes a little every frame keeps the temporal reprojection's marched pixels
  // apart from its history (a 2x2 or 4x4 dot pattern over the growing cloud while it grows), where a rebuild changes
  // it once and converges in a few frames; with the update spread, the rebuild's frame (the images and the grid,
  // about 75 ms on lavapipe) costs no more than the step's.
  bool growth_light_sweep = false;
};

// The march's settings of these options: the lighting preset with its overridden constants, and the rest.
CloudSettings cloud_settings(const CloudRenderOptions& o);

// A growing cloud's update spread over frames where --cloud-growth-update-frames does not say: 4 on a GPU (with the
// step's frame, 12 steps a second at 60 Hz, the talk's goal is 10), 8 on a CPU device (the sample storm's update is
// 190 ms of lavapipe's time: about 25 ms a frame; 9 frames a step still allow 2 steps a second at 20 fps, the
// storm takes 1.2).
int growth_update_frames_for_device(const CloudRenderOptions& o, bool cpu_device);

// The 40/60 Hz split's distance where --cloud-split-distance does not set it: the talk's 200 m on a GPU,
// kCpuSplitDistanceM on a CPU device. Issue 23 measured the lair (the Stormbird's chamber, whose walls stand
// 200-400 m from the camera) at 320x180 on lavapipe: split at 400 m, clouds 31.4 -> 22.9 ms at 60 Hz and
// its picture 50.6 dB from the 30 Hz one (50.9 at 200 m); the other six cameras have no cloud between
// 200 and 400 m and are unchanged. Beyond that the near layer's coarser pixels show (immersed at 800 m:
// 37.7 -> 33.8 dB).
constexpr float kCpuSplitDistanceM = 400.0f;
float split_distance_for_device(const CloudRenderOptions& o, bool cpu_device);

}  // namespace cumulo::clouds::render
