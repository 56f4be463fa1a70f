#pragma once
// The voxel-cloud renderer's passes (2023 talk, seed 000 "Sampling Density", "Lighting",
// "Ray-Marching", "30hz, 60hz, 40hz"), Wicked-style: a resources struct, its creation, and one
// function that adds this frame's passes to a render graph. The engine wiring (module stage hooks,
// snapshot extension, Cloudscape component) is a thin layer on top of these.
//
// [SECTION] Index
//   CloudAblation, CloudDebugView, CloudSettings   switches (talk's cost table, debug views, constants)
//   CloudInstance                                  one placed cloudscape (what a Cloudscape component maps to)
//   CloudFrameInputs                               everything one frame needs (camera, sun, instances)
//   CloudResources / create_cloud_resources        persistent GPU state (pipelines, light grids, history, UBOs)
//   add_cloud_passes                               the frame's passes -> the new scene colour
//
// [SECTION] Example
//   gpu::PipelineLibrary library(ctx);
//   clouds::render::CloudAssetCache assets(ctx);
//   auto res = clouds::render::create_cloud_resources(ctx, library, assets.noise(noise_file));
//   CloudFrameInputs in;
//   in.camera = snapshot.camera; in.frame_index = n; in.time = t; in.slot = frame.slot;
//   in.sun_direction = ...; in.sun_color = ...; in.ambient_color = ...;
//   CloudInstance inst;
//   inst.asset = assets.cloudscape(folder, default_cloud_formats(ctx.info()));
//   in.instances.push_back(inst);
//   hdr = clouds::render::add_cloud_passes(*res, graph, in, hdr, depth);   // before tonemap
//
// [SECTION] Passes (each a graph pass: debug label + timestamps)
//   clouds.light_grid  compute  reads the asset NVDFs + noise (imported, sampled); read_write the light
//                               grid (import_persistent, StorageWrite; one image, every instance's
//                               grid stacked along z). One eighth of each grid per frame (z slabs), all
//                               of an instance's grid when it is invalid or stale.
//   clouds.march       compute  30 Hz: one full-resolution march. Reads NVDFs, noise, light grids
//                               (sampled) and the scene depth (sampled); writes clouds.color (RGBA16F:
//                               radiance, transmittance) and clouds.depth (RGBA32F: opacity-0.5 distance,
//                               steps, segment end), transient.
//   clouds.march_near  compute  40/60 Hz: segment < split at half resolution -> clouds.near_color/depth
//                               (left out with split_merge when no box is within the split distance:
//                               clouds.march_far then marches the whole ray)
//   clouds.march_far   compute  40/60 Hz: segment >= split at full resolution -> clouds.far_color/depth
//                               (reads near_color: stops where the near layer is already opaque)
//   clouds.reconstruct compute  reprojection (CloudSettings::reprojection_block > 1, temporal on): the
//                               sub-sampled full-resolution march (30 Hz march or 40/60 Hz far) + its own
//                               history (import_history "clouds.reprojection") -> full-resolution colour/depth
//   clouds.split_merge compute  depth-aware upsample of near, merged over far -> clouds.color/depth (when the far
//                               segment is not reprojected, and for the split and profile debug views)
//   clouds.reconstruct_merge    the far segment's reconstruction with the merge in it (reprojected 40/60 Hz):
//                      compute  writes the far history and clouds.color/depth
//   clouds.temporal    compute  reads clouds.color/depth + last frame's history (sampled); writes this
//                               frame's history (import_history: render::GpuHistory "clouds.history").
//                               Left out where clouds.reconstruct or clouds.reconstruct_merge writes the
//                               march's final colour: they accumulate it themselves (CloudSettings::fuse_temporal)
//   clouds.composite   compute  reads the cloud colour (and depth, light grid for debug views);
//                               read_write hdr (StorageWrite): hdr * transmittance + radiance
//
// Every pass declares what it touches; barriers come from the graph. The assets are imported per graph
// in SHADER_READ_ONLY_OPTIMAL (they may be shared by several renderers); the light grid and the history
// are persistent graph textures (the graph remembers their state between frames).
#include <functional>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/core/enum_names.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/render_feature.h"
#include "engine/render/graph/render_graph.h"
#include "engine/scene/camera.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/scene/density_query.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

using cumulo::render::RenderGraph;
using cumulo::render::TextureHandle;

// The talk's cost table (seed 000 "Implementation of ray-march": Base -> + Voxel-Based Lighting ->
// + Adaptive & SDF Ray-March). Each builds its own pipeline (no dead branches in the loop).
enum class CloudAblation : uint8_t {
  Base,           // uniform step (CloudSettings::base_step_m) + 10-sample, 256 m light march per sample
  VoxelLighting,  // base stepping + 2 marched light samples, then the light grid
  Full,           // + SDF and adaptive step placement (the shipped method)
};
inline constexpr std::array kCloudAblationNames{EnumName<CloudAblation>{CloudAblation::Base, "base"},
                                                EnumName<CloudAblation>{CloudAblation::VoxelLighting, "voxel-lighting"},
                                                EnumName<CloudAblation>{CloudAblation::Full, "full"}};
inline const char* ablation_name(CloudAblation a) { return name_of(kCloudAblationNames, a); }

// How the light grid is computed (both give the same sums; the sweep is O(voxels) instead of
// O(voxels x ray length)).
enum class CloudLightGridMethod : uint8_t {
  Rays,   // the talk: a ray from every voxel to the grid boundary (light_grid_update.comp)
  Sweep,  // level by level from the light: each voxel adds its stretch to the next level's sum (light_grid_sweep.comp)
};
inline constexpr std::array kCloudLightGridMethodNames{EnumName<CloudLightGridMethod>{CloudLightGridMethod::Rays, "rays"},
                                                       EnumName<CloudLightGridMethod>{CloudLightGridMethod::Sweep, "sweep"}};
inline const char* light_grid_method_name(CloudLightGridMethod m) { return name_of(kCloudLightGridMethodNames, m); }

enum class CloudDebugView : uint8_t { None, Profile, Steps, LightGrid, Split };
inline constexpr std::array kCloudDebugViewNames{
    EnumName<CloudDebugView>{CloudDebugView::None, "none"}, EnumName<CloudDebugView>{CloudDebugView::Profile, "profile"},
    EnumName<CloudDebugView>{CloudDebugView::Steps, "steps"}, EnumName<CloudDebugView>{CloudDebugView::LightGrid, "light-grid"},
    EnumName<CloudDebugView>{CloudDebugView::Split, "split"}};
inline const char* debug_view_name(CloudDebugView v) { return name_of(kCloudDebugViewNames, v); }

// The most marched light samples before the light grid (CloudSettings::light_samples).
inline constexpr uint32_t kMaxLightSamples = 8;
// The most light-grid levels the multiple-scattering solve takes (its tiles' shared memory; the talk's grid has 32).
inline constexpr uint32_t kMaxSolveLevels = 32;

inline constexpr float kTalkAnimatedJitterDistanceM = 250.0f;
inline constexpr float kJitterAnimatedEverywhereM = 1e30f;

enum class CloudLights : uint8_t { All, Sun, Sky };
inline constexpr std::array kCloudLightsNames{EnumName<CloudLights>{CloudLights::All, "all"}, EnumName<CloudLights>{CloudLights::Sun, "sun"},
                                              EnumName<CloudLights>{CloudLights::Sky, "sky"}};

struct CloudSettings {
  CloudAblation ablation = CloudAblation::Full;
  CloudDebugView debug = CloudDebugView::None;
  bool split = false;              // 40/60 Hz: near half-res + far full-res (talk: < 200 m / > 200 m)
  bool temporal = true;            // temporal accumulation of the jittered march
  // With a reprojected march, its reconstruction accumulates as well (reconstruct.comp's TEMPORAL): one full-resolution
  // pass less (issue 23: about 1 ms at 320x180 on lavapipe), the history clamped to the marched samples' box instead of
  // the temporal pass's plus of its input. false: the separate clouds.temporal pass (tests compare the two).
  bool fuse_temporal = true;
  bool distance_noise_mip = true;  // false: noise mip 0 everywhere (the talk's "fixed MIP level")
  // The two marched light samples of voxel-lighting / full: true samples the noise by its mean (a 24 m
  // light sample integrates far more than the 0.8 m noise texel; about 20 % of the march on lavapipe);
  // false: the full up-rez sampler, the talk's "taken as we did before".
  bool light_sample_noise_mean = true;
  // 40/60 Hz: skip the near march and the merge when no cloudscape box comes within split_distance_m of
  // the camera (false: always run both, to measure them).
  bool skip_empty_near = true;
  float split_distance_m = 200.0f;          // talk: "< 200 Meters"
  // Within this distance the march's jitter changes every frame, beyond it stays (talk: "distance_from_camera < 250.0 ?
  // animated_hash : static_hash", kTalkAnimatedJitterDistanceM). Beyond 250 m a still camera kept one jitter's dither
  // at every cloud edge for good (a cut-out, speckled rim at 640x360); the temporal accumulation averages an animated
  // jitter at any distance, so the default animates it everywhere (--cloud-jitter animated|talk).
  float animated_jitter_distance_m = kJitterAnimatedEverywhereM;
  float jitter_scale = 1.0f;                // sample offset = hash * step * jitter_scale
  uint32_t max_steps = 256;                 // loop bound of the full march (a uniform, so lavapipe can exit early)
  uint32_t base_max_steps = 2048;           // loop bound of the base / voxel-lighting uniform march
  float base_step_m = 4.0f;                 // uniform step of base: half the talk's 8 m voxel
  float light_sample_m = 24.0f;             // length of the first marched light sample before the grid
  // The marched light samples before the grid: how many, and how much longer each is than the one before (the
  // talk: 2 of 24 m; issue 21's detail-aware samples: more and shorter near the point, growing toward the grid).
  uint32_t light_samples = 2;
  float light_sample_growth = 1.0f;
  float base_light_march_m = 256.0f;        // talk: "a 256 meter, 10 sample light ray march as we did before"
  uint32_t base_light_samples = 10;
  float extinction = 0.05f;    // 1/m per unit density (not in the talk: a thick cumulus reaches ~exp(-10) in 200 m)
  float albedo = 0.99f;        // single-scattering albedo of cloud droplets
  float transmittance_limit = 0.01f;  // early exit (talk: view_ray_transmittance_limit)
  // The in-cloud step (the talk's adaptive step) may grow up to this many times where a sample weighs little or
  // changes little: behind an optical depth, as 1 / sqrt(T) with T the view ray's transmittance so far (light
  // from behind an optical depth of 1 reaches the eye at a third of its strength or less), and in thin cloud,
  // until a step spans an optical depth of 0.1 at the last sample's extinction (march_render.comp). 1: the
  // talk's step everywhere (`--cloud-step-growth 1`).
  float step_growth = 4.0f;
  float hg_forward = 0.8f, hg_backward = -0.3f, hg_forward_weight = 0.7f;  // dual-lobe HG (silver lining)
  float ms_strength = 1.0f;           // weight of the multiple-scattering probability field
  // Its Beer-Lambert attenuation (talk: Remap(sun_dot, 0.0, 0.9, 0.25, ValueRemap(cloud_distance, -128.0, 0.0, 0.05,
  // 0.25))): the coefficient deep inside a cloud toward the sun, and at its surface or away from the sun.
  float ms_attenuation_inside = 0.05f, ms_attenuation = 0.25f;
  // The multiple-scattering field's falloff with the optical depth toward the sun: false, the talk's
  // Beer-Lambert exp(-od x attenuation); true, diffusion's 1 / (1 + 0.75 (1 - g) od) (g = hg_forward: the
  // transport mean free path of a forward-peaked phase function), which a thick base does not turn black.
  bool ms_diffusion = false;
  // With ms_diffusion: the own cloud's optical depth away from the sun too (the light grid's w), a slab's linear
  // fluence (march_render.comp): the middle of a thick cloud is not as dark as its far side.
  bool ms_slab = false;
  // With ms_diffusion: the own cloud goes on across air under at least this sky optical depth (enclosed air: a
  // chamber inside a cloud) rather than ending at the first air along the sun's line (0: it ends there). Needs the
  // sweep's light grid (the talk's rays end the own cloud at the first air).
  float ms_enclosed_sky_depth = 0.0f;
  // With ms_slab: the ground's albedo for the light it bounces up into the clouds' bases (0: none).
  float ground_albedo = 0.0f;
  // With ms_slab: the multiple scattering's forward lobe near the lit surface, as a fraction of the phase's mean
  // cosine (march_render.comp; 0: isotropic, the talks').
  float ms_anisotropy = 0.0f;
  // With ms_slab: how far the slab's falloff takes the sun's incidence on a horizontal face where the sun's line leaves
  // the own cloud through its top (march_render.comp; 0: the light enters a face square to the sun, as before).
  float ms_incidence = 0.0f;
  // With ms_slab and the dark edges: how far a surface that the view ray reached from a chamber's air (enclosed air,
  // see ms_enclosed_sky_depth, with the own cloud away from the sun as deep) loses its edge darkening, because the
  // chamber's walls send back the light it loses (march_render.comp; 0: every surface darkens, as before).
  float ms_cavity = 0.0f;
  // With ms_slab and the ambient direction: the sky's light also through the nearest surface, which a face of normal n
  // sees (1 + n.y) / 2 of the sky's hemisphere through, times this (march_render.comp; 0: the column straight up only).
  float sky_side = 0.0f;
  // With ms_slab and the silver lining: the light the phase's forward lobe scatters past the first order, which goes on
  // near the sun's direction and so reaches deeper than the direct light (march_render.comp; 0: none, the talks').
  float ms_forward = 0.0f;
  // With ms_slab: the envelope clouds' sun light past the first order at least this times diffusion's through the
  // optical depth toward the sun, where the octaves fall off faster (envelope_march.comp octave_light; 0: the octaves).
  float envelope_ms_diffused = 0.0f;
  // With ms_slab: the share of the phase's eccentricity each envelope octave keeps from the one before (Wrenninge's c).
  float envelope_eccentricity = 0.0f;
  // With ms_slab: the envelope clouds' light samples erode by the detail noise's mean, as the view ray's density is
  // eroded by the sampled detail (envelope_march.comp light_optical_depth; off: the talk's, no erosion toward the sun).
  bool envelope_light_erosion = false;
  // With ms_slab: the dark edges from the optical depth to the nearest surface, 1 - exp(-this x depth) (0: the
  // talks' profile).
  float edge_depth_scale = 0.0f;
  // Other instances' clouds shadow an instance's (the sun's and the sky's optical depth through their light grids,
  // light_grid_lookup.glsl); the talks' grid is per cloudscape, so off there.
  bool instance_shadows = false;
  // The clouds' sky light is the sky's mean radiance over the upper hemisphere (SceneLighting::sky_mean), not
  // 0.5 (zenith + horizon), which is about twice as bright and, at a low sun, warm where the sky is blue.
  bool sky_mean_ambient = false;
  // Without sky_mean_ambient: the sky light keeps 0.5 (zenith + horizon)'s luminance, which the lighting model's sky
  // transport was calibrated with, in the hue of the hemisphere's mean. The path tracer's sky-lit clouds take the
  // mean's hue (issue 21, session 59: blue / red 3.2 at noon and 1.2 at dusk in the reference, the mean's own; 2.1
  // and 0.5 with the zenith and horizon's, whose bright band at the horizon is orange at dusk).
  bool sky_mean_hue = false;
  // Which lights reach the clouds (cumulo fidelity --cloud-lights): all, the sun alone or the sky alone, so each
  // source's share of the lighting model can be measured against the path tracer's with the same source alone.
  CloudLights lights = CloudLights::All;
  // With ms_slab: the lateral leak's coefficient c (march_render.comp): where the nearest surface lies nearer than
  // both ends of the sun's line through the own cloud (a tower's top under a grazing sun), the multiple scattering
  // falls by exp(-c tau'_excess / (2 tau'_surface + 4/3)) (transport optical depths). 0: none.
  float ms_lateral = 0.0f;
  // The multiple scattering solved by diffusion on the light grid (light_grid_diffusion.comp) instead of the slab's
  // falloff along the sun's line: the cloud's shape decides where diffused light leaks out (bases, tops, chambers).
  // Solved by tiles of 8x8 columns, each relaxed ms_solve_local_iterations times red-black (over-relaxed by
  // ms_solve_omega) per visit; ms_solve_iterations rounds over every tile after a full rebuild of a grid (one when
  // the last solve is recent: it starts from that solution), ms_solve_update_iterations after a partial update (the
  // sun moving less than sun_rebuild_degrees; 0: none, the field lags by less than that). On lavapipe a whole solve (4 rounds)
  // costs about 170 ms per instance of the CPU grid; 4 rounds are within 67 dB of 16 (the sample's ground view).
  bool ms_solve = false;
  // The multiple scattering's falloff: mix(the slab's x ms_strength, the solved fluence x ms_solve_strength,
  // ms_solve_weight).
  float ms_solve_weight = 1.0f;
  float ms_solve_strength = 1.0f;
  uint32_t ms_solve_iterations = 4;
  uint32_t ms_solve_update_iterations = 0;
  uint32_t ms_solve_local_iterations = 8;
  float ms_solve_omega = 1.8f;
  // With ms_diffusion: the Beer-Lambert coefficient (x od) of the optical depth toward the sun that lies in other
  // clouds than the sample's own (the light grid's z channel tells them apart): diffused light leaves a cloud in
  // every direction, so little of what crossed one cloud reaches another across the air. 0: no difference.
  float ms_other_cloud_attenuation = 0.0f;
  float ambient_occlusion_scale = 0.1f;   // sky optical depth = summed sky density x extinction x this (not in the talk)
  float noise_mip_distance_scale = 0.002f;  // talk's cVoxelFineDetailMipMapDistanceScale (value not given)
  float temporal_blend = 0.1f;        // weight of the new frame in the accumulation
  // Temporal reprojection of the full-resolution march (2015 talk: "1 of 16 pixels per frame"): with
  // temporal on, the 30 Hz march and the 40/60 Hz far segment march one pixel of every BxB block per
  // frame (B = reprojection_block) and clouds.reconstruct reprojects the rest from the last frame.
  // 1: every pixel every frame (the 2023 talk's method); 2: 1 of 4; 4: 1 of 16 (the 2015 talk);
  // 0: by budget mode (apply_budget_mode's default: 1 of 4 at 30 Hz, 1 of 16 for the 40/60 Hz far segment,
  // whose near layer is marched every frame at half resolution).
  uint32_t reprojection_block = 0;
  // The 40/60 Hz near segment (half resolution) marches one pixel of each BxB block per frame too and reprojects
  // the rest, B this (1: every half-resolution pixel every frame). The talk gives the near pass's resolution
  // (480x270 for 960x540), not its reprojection; at 2 the near pass marches as many rays as the far one's 1 in 16, at 4
  // (the default, issue 23) a quarter of those: the 2015 talk's 1 in 16 of its own pixels. Flying out of a cloud's
  // flank (content/levels/sample/paths/fly_out_of_flank.json, 320x180, 60 Hz), frames 60 / 150 / 300 against marching
  // every near pixel: 53.2 / 45.2 / 60.8 dB (1 in 4: 55.9 / 51.4 / 62.0); inside the Stormbird's chamber the near
  // march 11.3 -> ~3.5 ms on lavapipe.
  uint32_t near_reprojection_block = 4;
  float light_grid_debug_height = 0.5f;  // light-grid debug view: slice height in the box, 0..1
  float sun_rebuild_degrees = 1.0f;   // the sun moving more than this since the last full rebuild -> rebuild
  CloudLightGridMethod light_grid_method = CloudLightGridMethod::Sweep;
  // Sweep: keep the level-by-level updates going while the sun is still (as when it moves; for measuring).
  bool light_grid_always_update = false;
  bool shadows = true;  // the clouds' shadow on the scene (clouds.shadow_map -> render::LightShadowMap)
  bool terrain_shadow = true;  // the terrain's shadow on the clouds (CloudFrameInputs::terrain_depth)
  // The talks' lighting effects in the march (CLOUD_EFFECT_* bits, cloud_params.h); all on by default.
  uint32_t effects = CLOUD_EFFECTS_ALL;
};

// The named effects (cumulo fidelity measures each): "silver-lining", "dark-edges", "inner-glow",
// "long-shadows", "ambient-direction", "lightning-glow".
struct CloudEffectName {
  const char* name;
  uint32_t bit;
};
inline constexpr CloudEffectName kCloudEffects[] = {
    {"silver-lining", CLOUD_EFFECT_SILVER_LINING}, {"dark-edges", CLOUD_EFFECT_DARK_EDGES},
    {"inner-glow", CLOUD_EFFECT_INNER_GLOW},       {"long-shadows", CLOUD_EFFECT_LONG_SHADOWS},
    {"ambient-direction", CLOUD_EFFECT_AMBIENT_DIRECTION}, {"lightning-glow", CLOUD_EFFECT_LIGHTNING_GLOW}};
// The bit of an effect's name; 0 if unknown.
uint32_t cloud_effect_bit(std::string_view name);

// The lighting model's free constants: the talks' (Talk: CloudSettings as declared) or the set
// tuned against the path-traced reference (Tuned; cumulo fidelity measures both). Only terms the reference
// does not share change (the multiple-scattering strength, the ambient occlusion scale), so both sets march
// the same medium and phase function as the reference. (Also the inner glow's relaxed attenuation.)
// Diffusion (issue 21): the multiple-scattering field falls off as diffusion does through the sample's own cloud
// and by Beer-Lambert across other clouds (CloudSettings::ms_diffusion, ms_other_cloud_attenuation).
// Slab (the engine's default, cloud_feature.h; issue 21): diffusion's with a slab's fluence along the sun's line
// (ms_slab), enclosed air (ms_enclosed_sky_depth), the sky from the upper hemisphere at its full optical depth,
// its diffused light, a ground bounce (ground_albedo) and a forward lobe of the multiple scattering
// (ms_anisotropy); docs/fidelity/diffusion_lighting.md has what each measured.
// Solve (issue 21): the slab's terms with the sun's multiple scattering solved by diffusion on the light grid
// (ms_solve) blended half and half with the slab's falloff.
enum class CloudLightingPreset : uint8_t { Talk, Tuned, Diffusion, Slab, Solve };
inline constexpr std::array kCloudLightingPresetNames{
    EnumName<CloudLightingPreset>{CloudLightingPreset::Talk, "talk"}, EnumName<CloudLightingPreset>{CloudLightingPreset::Tuned, "tuned"},
    EnumName<CloudLightingPreset>{CloudLightingPreset::Diffusion, "diffusion"},
    EnumName<CloudLightingPreset>{CloudLightingPreset::Slab, "slab"},
    EnumName<CloudLightingPreset>{CloudLightingPreset::Solve, "solve"}};
inline const char* lighting_preset_name(CloudLightingPreset p) { return name_of(kCloudLightingPresetNames, p); }
void apply_lighting_preset(CloudSettings& s, CloudLightingPreset p);
// World metres the marched light samples span before the light grid takes over (the march's P.light_march.z).
float marched_light_reach_m(const CloudSettings& s);

// Budget modes (DESIGN.md; talk "30hz, 60hz, 40hz"): 30 Hz = one full-resolution march; 40 and 60 Hz =
// the near segment (< split_distance_m) at half resolution and the far one at full resolution.
inline void apply_budget_mode(CloudSettings& s, int hz) { s.split = hz >= 40; }
// The reprojection block in effect (CloudSettings::reprojection_block; 0 = by mode).
inline uint32_t reprojection_block(const CloudSettings& s) {
  if (!s.temporal) return 1;
  if (s.reprojection_block == 0) return s.split ? 4 : 2;
  return s.reprojection_block > 4 ? 4 : s.reprojection_block;
}
// The near segment's (40/60 Hz, half resolution): 1 without temporal accumulation or the split.
inline uint32_t near_reprojection_block(const CloudSettings& s) {
  if (!s.temporal || !s.split) return 1;
  return s.near_reprojection_block < 1 ? 1 : s.near_reprojection_block > 4 ? 4 : s.near_reprojection_block;
}

// One placed cloudscape. A Cloudscape ECS component (+ its entity's Transform) maps onto this 1:1;
// several instances may share one asset (one GPU copy; each gets its own light grid); a frame may hold
// two distinct assets (a cloudscape and a hero cloud: the march binds both, see CLOUD_ASSET_SLOTS).
// The placement (position, rotation, uniform scale, density, wind, dissipation, coverage: CloudPlacement,
// scene/density_query.h, which the CPU density query shares) plus the asset on the GPU.
struct CloudInstance : CloudPlacement {
  std::shared_ptr<const CloudAsset> asset;
  // Its asset's images changed this frame (a grown cloud stepped, cloud_growth_runtime.h): its light grid is rebuilt.
  bool asset_changed = false;
  // Its images changed by a little this frame (a grown cloud's step): with the sweep method its light grid is swept
  // again over the next cycle of frames, from the level nearest the light, instead of rebuilt in this one (a rebuild
  // is the update's most expensive part on a CPU device). Rebuilt anyway where the grid is not current otherwise.
  bool asset_grew = false;
};

// Its block of CloudParams (transform, box, sun and sky in asset space, density, dissipation, wind
// scroll, coverage) for a frame at `time` with the sun toward `sun_direction`.
shared::CloudInstanceParams cloud_instance_params(const CloudInstance& inst, glm::vec3 sun_direction, double time);
// World AABB of an instance's transformed box (conservative for a rotated box).
void instance_world_bounds(const CloudInstance& inst, glm::vec3& lo, glm::vec3& hi);

struct CloudFrameInputs {
  scene::CameraView camera;
  uint64_t frame_index = 0;  // animates the jitter and picks the light-grid slab
  double time = 0.0;         // simulation seconds (wind scroll)
  uint32_t slot = 0;         // frame-in-flight slot (gpu::FrameRing): which uniform buffer
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};  // unit, toward the sun
  glm::vec3 sun_color{1.0f};                  // colour x illuminance (linear)
  glm::vec3 ambient_color{0.3f, 0.4f, 0.5f};  // sky ambient (linear)
  // The sky's irradiance on a horizontal ground / pi (SceneLighting::sky_irradiance, times its ambient scale), the
  // sky's share of the light the ground bounces into the clouds; 0: not known, ambient_color stands for it.
  glm::vec3 ground_sky{0.0f};
  // Aerial perspective in the composite: the terrain's height fog (SceneLighting fog_*) toward the sky's
  // zenith/horizon colours; density 0 leaves the clouds unhazed.
  float haze_density = 0.0f, haze_falloff = 0.001f;
  glm::vec3 sky_zenith{0.0f}, sky_horizon{0.0f};
  std::vector<CloudInstance> instances;       // at most kMaxInstances, of at most kMaxAssets assets
  // Each instance's index in the frame's CloudFrame::instances (an asset the GPU memory budget cannot hold is left
  // out, so the two lists need not line up).
  std::vector<uint32_t> frame_instances;
  std::vector<CloudPointLight> lights;        // at most kMaxPointLights
  // The 2.5D sky's half-resolution result (SkyLayer::add_passes), composited with the voxel clouds in
  // the order of their depths; invalid: no 2.5D sky.
  TextureHandle sky_color, sky_depth;
  // The Envelope method's orographic clouds (EnvelopeLayer::add_passes): a third layer in the composite; with the
  // 40/60 Hz split also their near pass (half their resolution), merged over the far one. Invalid: none.
  TextureHandle envelope_color, envelope_depth, envelope_near_color, envelope_near_depth;
  bool envelope_upsample = false;  // envelope_color is below the output's size
  // The same clouds as a medium for the path tracer (EnvelopeLayer::add_medium; reference_tracer.h): their parameter
  // block (shared::EnvelopeParams) and textures at envelope_params.h's ENV_BINDING_SHAPE.. order. Invalid: none.
  struct EnvelopeMedium {
    VkBuffer params = VK_NULL_HANDLE;
    TextureHandle shape, steps, aux, base_noise, detail_noise;
    bool valid() const { return params != VK_NULL_HANDLE && shape.valid(); }
  };
  EnvelopeMedium envelope_medium;
  // The atmosphere's aerial-perspective froxels (render::AerialPerspective, a stage resource): the composite
  // hazes each layer with them at its depth; invalid: the height fog (haze_*).
  TextureHandle aerial;
  // The geometry's depth from the key light (render::LightDepth): where the terrain hides the sun from
  // a cloud sample, its direct light goes (TERRAIN_SHADOW march variant); invalid: no terrain shadow.
  TextureHandle terrain_depth;
  glm::mat4 terrain_depth_matrix{1.0f};
  float terrain_depth_range_m = 1.0f;
  // The voxel clouds' shadow map this frame (CloudLightOutputs::shadow, on the plane under their boxes): the envelope
  // clouds below them read it (envelope_march.comp VOXEL_SHADOW); invalid: none.
  cumulo::render::LightShadowMap voxel_shadow;
  bool camera_cut = false;                    // history invalid this frame
  // The march, its reconstruction and history and the 2.5D sky at this fraction of the output's width and
  // height (dynamic resolution, FrameSnapshot::resolution_scale); the composite upsamples them depth-aware.
  float resolution_scale = 1.0f;
  bool rebuild_light_grid = false;            // force a full light-grid rebuild
  CloudSettings settings;
};

// The engine-side fields of CloudFrameInputs from a frame snapshot: camera, frame index, time, the budget
// mode (apply_budget_mode), the sun and the ambient; the module adds its instances, lights and other
// settings. Units: the engine's sun radiance (SceneLighting::sun_radiance, the geometry's) is what a white
// Lambertian surface returns (E / pi); the march multiplies the sun by a phase function in 1/sr, so its sun
// colour is pi x that radiance. The
// ambient is the stand-in sky's hemispheric term as geometry_lit.frag uses it (mean of zenith and
// horizon x ambient scale): a thick cloud under a uniform sky scatters about the sky's radiance.
// Distance from the camera to the nearest instance's world box (0 inside one; infinity with none).
float nearest_instance_distance(const CloudFrameInputs& in);

CloudFrameInputs cloud_inputs_from_snapshot(const cumulo::render::FrameSnapshot& snapshot, uint32_t slot,
                                            const CloudSettings& settings = {});
// The clouds' sky light (before SceneLighting::ambient): 0.5 (zenith + horizon), the hemisphere's mean
// (CloudSettings::sky_mean_ambient), or the former's luminance in the latter's hue (sky_mean_hue); the two colours
// where the atmosphere left the mean unset.
glm::vec3 cloud_sky_light(const cumulo::render::SceneLighting& lighting, const CloudSettings& settings);

// The march's parameter block for a frame (what add_cloud_passes uploads; no history): other passes that
// read the same density field and lighting (the path-traced reference) bind it too. `slots`: the asset slot
// of each instance (CloudLightOutputs::slots; missing entries are slot 0).
shared::CloudParams cloud_params(const CloudFrameInputs& in, VkExtent2D size, const std::vector<uint32_t>& slots);
// The ground's radiance per unit albedo under the frame's sun and sky: what the slab's ground bounce reflects into the
// clouds (CloudParams::ground_light).
glm::vec3 ground_radiance(const CloudFrameInputs& in);

inline constexpr uint32_t kMaxInstances = 4;    // CLOUD_MAX_INSTANCES
inline constexpr uint32_t kMaxPointLights = kMaxCloudPointLights;  // CLOUD_MAX_POINT_LIGHTS
inline constexpr uint32_t kMaxAssets = 3;       // CLOUD_MAX_ASSETS: distinct assets among the instances
// Each asset slot's bindings in the march and the path tracer (cloud_params.h).
inline constexpr uint32_t kModelingBinding[kMaxAssets] = {CLOUD_BINDING_MODELING, CLOUD_BINDING_MODELING_1,
                                                           CLOUD_BINDING_MODELING_2};
inline constexpr uint32_t kFieldBinding[kMaxAssets] = {CLOUD_BINDING_FIELD, CLOUD_BINDING_FIELD_1, CLOUD_BINDING_FIELD_2};
inline constexpr uint32_t kCoverageBinding[kMaxAssets] = {CLOUD_BINDING_COVERAGE, CLOUD_BINDING_COVERAGE_1,
                                                           CLOUD_BINDING_COVERAGE_2};
inline constexpr uint32_t kFieldFairBinding[kMaxAssets] = {CLOUD_BINDING_FIELD_FAIR, CLOUD_BINDING_FIELD_FAIR_1,
                                                            CLOUD_BINDING_FIELD_FAIR_2};

struct CloudResourcesDesc {
  // The talk's grid on GPUs; on CPU devices (lavapipe) 96x16x96 (43 x 32 x 43 m voxels over the sample's
  // 4 km box) updated over 16 frames, which keeps an updating grid under 5 % of the cloud time there (the
  // talk's grid, even swept, costs about as much as the march). The two marched light samples before the
  // grid keep the detail near cloud surfaces either way.
  static CloudResourcesDesc for_device(const gpu::DeviceInfo& device);
  glm::uvec3 light_grid_size{256, 32, 256};  // the talk's 256x256x32 with its Z-up as our Y-up
  uint32_t light_grid_divisions = 8;         // "amortized over 8 frames": z slabs updated per frame
  // Loop bounds of the grid's sphere-traced rays: inside cloud a step is one grid voxel (16 m for the
  // sample), so 64 steps cover 1 km of cloud toward the sun and 32 the 512 m layer above a voxel.
  uint32_t light_grid_sun_steps = 64;
  uint32_t light_grid_sky_steps = 32;
  // Sweep: at most this many density samples along one voxel's stretch to the next level (a low sun's
  // stretch is up to 20 levels long; samples are spaced at least a voxel apart below this bound). Issue 21:
  // 8 spaced a 2.7-degree sun's samples 80-200 m apart on the CPU grid, and the clouds' gaps and cores between
  // them went unseen: 32 took the long_shadows view from 43.4 to 39.7 % (64 spp), no other view moved, and a
  // full rebuild at that sun costs 170 ms instead of 134 (320x180, lavapipe); a high sun takes fewer anyway.
  uint32_t light_grid_sweep_samples = 32;
  // The clouds' shadow map on the scene (clouds.shadow_map): texels per side over the boxes' footprint
  // along the light (the sample's 4 km box at noon: 8 m texels at 512, as the light grid's own 16 m
  // voxels need no finer; 128 on CPU devices).
  uint32_t shadow_map_size = 512;
};

struct CloudResources;  // defined in cloud_renderer.cpp
struct CloudResourcesDeleter {
  void operator()(CloudResources* r) const;
};
using CloudResourcesPtr = std::unique_ptr<CloudResources, CloudResourcesDeleter>;

// Pipelines come from `library` (hot reload covers the cloud shaders); `noise` is shared by every
// cloudscape. Throws cumulo::Error when a shader fails to build or the device lacks push descriptors.
CloudResourcesPtr create_cloud_resources(gpu::Context& ctx, gpu::PipelineLibrary& library,
                                         std::shared_ptr<const CloudNoise> noise, const CloudResourcesDesc& desc = {});

// Adds this frame's cloud passes and returns the new version of `hdr` (R16G16B16A16F, output size;
// gets storage usage). `depth` is the scene depth (D32F reversed-Z), read only. With no instance it
// adds nothing and returns `hdr`. Throws cumulo::Error for more instances, assets or lights than the limits.
// `outputs` (optional) receives the cloud colour and depth of this frame (after temporal accumulation
// when on), e.g. for aerial perspective or a test readback.
struct CloudPassOutputs {
  TextureHandle color;  // RGBA16F: rgb in-scattered radiance, a transmittance
  TextureHandle depth;  // RGBA32F: x distance where opacity reached 0.5 (else first cloud sample, else 1e6), y steps, z segment end
};
// The light passes alone (the light grid and the clouds' shadow map), for Stage::BeforeScene, so the
// geometry can read the shadow; add_cloud_passes then takes them instead of adding its own. The
// handles are of this graph only.
struct CloudLightOutputs {
  TextureHandle grid;                      // the light grid after this frame's update
  TextureHandle local;                     // what the march reads of the grids at a sample (light_grid_local.comp)
  TextureHandle ms_field;                  // CloudSettings::ms_solve: the solved multiple scattering (else invalid)
  cumulo::render::LightShadowMap shadow;   // texture invalid: no shadow this frame (light too low, off)
  std::vector<TextureHandle> modelings, fields;  // the assets' imports, by slot
  std::vector<TextureHandle> coverages;          // their coverage textures (coverage_texture only), by slot
  std::vector<TextureHandle> fairs;              // their fair-weather fields (the march's), by slot
  TextureHandle noise;
  std::vector<uint32_t> slots;  // asset slot of each instance
  int asset_slots = 1;
  bool bc1 = false;
  bool coverage_texture = false;  // the BC1 modeling NVDF: the coverage thresholds are a texture of their own (COVERAGE_TEXTURE)
};
CloudLightOutputs add_cloud_light_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in);
// `before_composite` (optional): called with the march's colour and depth (after temporal accumulation) and a copy of
// `in` before the composite, which then takes that copy: the 2.5D sky adds its passes there (sky_color, sky_depth), as
// it leaves out what the voxel clouds hide.
using BeforeComposite = std::function<void(const CloudPassOutputs& voxel, CloudFrameInputs& in)>;
TextureHandle add_cloud_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, TextureHandle hdr,
                               TextureHandle depth, CloudPassOutputs* outputs = nullptr,
                               const CloudLightOutputs* light = nullptr, const BeforeComposite& before_composite = {});

// The shadow map's plane (at the lowest box's bottom) and extent (every box's footprint along the
// light), or none: shadows off, no instance, or the light lower than kShadowMinLightHeight (sin of
// its elevation, about 1.1 degrees: there the footprint reaches 50 km for a 1 km-deep layer; 0.05 before issue 21's
// seventeenth session, which left the sample's low-sun view, 2.7 degrees, without the clouds' long shadows on the sea
// that the path tracer shows).
inline constexpr float kShadowMinLightHeight = 0.02f;
std::optional<cumulo::render::LightShadowMap> shadow_plane(const CloudFrameInputs& in, uint32_t texels);

// For tests and `cumulo bench`: GPU memory of the persistent cloud resources (light grids, history)
// and how many full light-grid rebuilds happened.
uint64_t persistent_gpu_bytes(const CloudResources& res);
uint32_t light_grid_rebuilds(const CloudResources& res);
uint32_t shadow_map_updates(const CloudResources& res);  // frames the clouds' shadow map was recomputed

}  // namespace cumulo::clouds::render
