// Parameters of the voxel-cloud passes (modules/clouds/render), shared by C++ and GLSL.
// 2023 talk (seed 000): "Sampling Density", "Lighting", "Ray-Marching", "30hz, 60hz, 40hz".
// One CloudParams uniform buffer per frame slot, filled by clouds::render::add_cloud_passes from
// CloudFrameInputs; per-dispatch variants (near/far segment, light-grid slab) go in push constants.
//
// Spaces: "world" is the engine's (metres, +Y up). "asset" is the cloudscape asset's own space, the
// world box its NVDF headers name (bounds_min..bounds_max); an instance places the asset with a
// transform (position, rotation, uniform scale): world = position + rotation * (scale * asset).
#ifndef CUMULO_SHARED_CLOUD_PARAMS_H
#define CUMULO_SHARED_CLOUD_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

// ---- Limits and binding numbers (set 0, push descriptors) ----------------------------------------
#define CLOUD_MAX_INSTANCES 4  // instances drawn by one march (each has its own light grid)
#define CLOUD_MAX_POINT_LIGHTS 4
#define CLOUD_MAX_ASSETS 3  // distinct cloudscape assets in one frame (define CLOUD_ASSET_SLOTS: 1, 2 or 3)
#define CLOUD_LOCAL_SIZE 8  // 8x8 work groups for the 2D passes (lavapipe runs 8 lanes at a time)

// light_grid_update.comp and march_render.comp
#define CLOUD_BINDING_PARAMS 0      // uniform CloudParams
#define CLOUD_BINDING_MODELING 1    // sampler3D: r profile, g detail type, b density scale, a coverage threshold (RGBA8)
#define CLOUD_BINDING_FIELD 2       // sampler3D: signed distance (R16 0..1, or the conservative BC1 rgb)
#define CLOUD_BINDING_NOISE 3       // sampler3D: voxel noise (R/G Curly-Alligator low/high, B/A Alligator low/high)
#define CLOUD_BINDING_LIGHT_GRID 4  // sampler3D: x summed density toward the sun, y toward the sky; instance i in z slab i
#define CLOUD_BINDING_SCENE_DEPTH 5 // sampler2D: scene depth (reversed-Z, D32F)
#define CLOUD_BINDING_OUT_COLOR 6   // image2D rgba16f: rgb in-scattered radiance, a transmittance
#define CLOUD_BINDING_OUT_DEPTH 7   // image2D rg32f: x distance where opacity reached 0.5 (or segment end), y steps
#define CLOUD_BINDING_GRID_OUT 8    // image3D rg16f: the light grid being updated (all slabs)
#define CLOUD_BINDING_NEAR_IN 9     // sampler2D: the far march reads the near layer's transmittance (early exit)
#define CLOUD_BINDING_MODELING_1 10 // sampler3D: the second asset's modeling NVDF (CLOUD_ASSET_SLOTS 2)
#define CLOUD_BINDING_FIELD_1 11    // sampler3D: the second asset's signed distance
#define CLOUD_BINDING_TERRAIN_DEPTH 13  // sampler2D (TERRAIN_SHADOW 1): the geometry's depth from the key light
// COVERAGE_TEXTURE 1 (the BC1 modeling NVDF has no alpha): each asset's coverage thresholds (coverage.nvdf, R8)
// (14..24 are the path tracer's, reference_params.h)
#define CLOUD_BINDING_COVERAGE 25    // sampler3D: slot 0's coverage thresholds
#define CLOUD_BINDING_COVERAGE_1 26  // sampler3D: slot 1's
// march_render.comp: each asset's fair-weather field (field_fair.nvdf, R16 at half resolution; a 1-texel -256 m
// stand-in without one): the conservative distance to the cloud whose coverage threshold is below
// CLOUD_COVERAGE_BAND, for the air steps while the weather's coverage leaves every other cloud absent
#define CLOUD_BINDING_FIELD_FAIR 27
#define CLOUD_BINDING_FIELD_FAIR_1 28
// The multiple scattering solved by diffusion on the light grid (CloudSettings::ms_solve; light_grid_diffusion.comp
// writes it, the march's MS_FIELD variant reads w): x source, y extinction, z the voxel's kind, w the fluence
#define CLOUD_BINDING_MS_FIELD 29    // sampler3D (march_render.comp, MS_FIELD 1)
#define CLOUD_BINDING_MS_OUT 30      // image3D rgba16f (light_grid_diffusion.comp)
// What the march reads of the light grids at a sample (light_grid_local.comp writes it after the grids change): x, y the
// other instances' summed density toward the sun and the sky, z the own sky sum, w the own sum away from the sun
#define CLOUD_BINDING_LIGHT_LOCAL 31  // sampler3D (march_render.comp)
#define CLOUD_BINDING_LOCAL_OUT 32    // image3D rgba16f (light_grid_local.comp)
// A third asset (CLOUD_ASSET_SLOTS 3: a cloudscape, a hero cloud and a cloud grown during play); 32..37 are the
// envelope's in reference_trace.comp (ENV_BINDING_REFERENCE_OFFSET)
#define CLOUD_BINDING_MODELING_2 40
#define CLOUD_BINDING_FIELD_2 41
#define CLOUD_BINDING_COVERAGE_2 42
#define CLOUD_BINDING_FIELD_FAIR_2 43
// shadow_map.comp (reads PARAMS and LIGHT_GRID)
#define CLOUD_BINDING_SHADOW_OUT 12  // image2D r16f: the key light's transmittance on the shadow plane
// temporal_accumulate.comp
#define CLOUD_BINDING_CURRENT 1         // sampler2D: this frame's march colour
#define CLOUD_BINDING_CURRENT_DEPTH 2   // sampler2D: this frame's march depth
#define CLOUD_BINDING_HISTORY 3         // sampler2D: last frame's accumulated colour
#define CLOUD_BINDING_ACCUM_OUT 4       // image2D rgba16f: accumulated colour
// split_merge.comp
// reconstruct.comp with MERGE_NEAR 1 (the far segment's reconstruction merges the near layer in, as split_merge.comp):
#define CLOUD_BINDING_RECON_NEAR 8          // sampler2D: half-resolution near colour
#define CLOUD_BINDING_RECON_NEAR_DEPTH 9    // sampler2D: half-resolution near depth
#define CLOUD_BINDING_RECON_MERGED 10       // image2D rgba16f: near over far
#define CLOUD_BINDING_RECON_MERGED_DEPTH 11 // image2D rgba32f
// reconstruct.comp with TEMPORAL 1 (the clouds' reconstruction accumulates as temporal_accumulate.comp does):
#define CLOUD_BINDING_RECON_TEMPORAL_HISTORY 12  // sampler2D: last frame's accumulated colour
#define CLOUD_BINDING_RECON_TEMPORAL_OUT 13      // image2D rgba16f: this frame's accumulated colour
#define CLOUD_BINDING_NEAR 1        // sampler2D: half-resolution near colour (< split distance)
#define CLOUD_BINDING_NEAR_DEPTH 2  // sampler2D: half-resolution near depth
#define CLOUD_BINDING_FAR 3         // sampler2D: full-resolution far colour
#define CLOUD_BINDING_FAR_DEPTH 4   // sampler2D: full-resolution far depth
#define CLOUD_BINDING_MERGED 6      // image2D rgba16f (same as OUT_COLOR)
#define CLOUD_BINDING_MERGED_DEPTH 7
// composite_apply.comp
#define CLOUD_BINDING_CLOUDS 1      // sampler2D: cloud colour (rgb radiance, a transmittance)
#define CLOUD_BINDING_HDR 2         // image2D rgba16f: scene colour, read-modify-write
#define CLOUD_BINDING_DEBUG_GRID 3  // sampler3D: the light grid (debug view shows instance 0)
#define CLOUD_BINDING_CLOUD_DEPTH 4 // sampler2D: cloud depth/steps (steps debug view)
#define CLOUD_BINDING_SKY_COLOR 5   // sampler2D (SKY_LAYER 1): the 2.5D sky at half resolution (rgb radiance, a transmittance)
#define CLOUD_BINDING_SKY_DEPTH 6   // sampler2D (SKY_LAYER 1): its depth (x opacity-0.5 distance)
#define CLOUD_BINDING_SCENE_DEPTH_COMPOSITE 7  // sampler2D (SKY_LAYER 1): the scene depth (the upsample stops at geometry)
#define CLOUD_BINDING_AERIAL 8      // sampler3D (AERIAL 1): the atmosphere's aerial-perspective froxels
#define CLOUD_BINDING_ENVELOPE_COLOR 9   // sampler2D (ENVELOPE 1): the orographic clouds (rgb radiance, a transmittance)
#define CLOUD_BINDING_ENVELOPE_DEPTH 10  // sampler2D (ENVELOPE 1): their depth (x opacity-0.5 distance, z the ray's end)
#define CLOUD_BINDING_ENVELOPE_NEAR_COLOR 11  // sampler2D (ENVELOPE_SPLIT 1): their near pass (half resolution)
#define CLOUD_BINDING_ENVELOPE_NEAR_DEPTH 12

// Debug views (CloudParams::frame.w).
#define CLOUD_DEBUG_NONE 0
#define CLOUD_DEBUG_PROFILE 1     // dimensional profile accumulated along the ray (grey)
#define CLOUD_DEBUG_STEPS 2       // steps per pixel, heat map (blue 0 .. red max_steps)
#define CLOUD_DEBUG_LIGHT_GRID 3  // a slice of instance 0's light grid (sun channel red, sky green)
#define CLOUD_DEBUG_SPLIT 4       // near segment tinted orange, far segment blue

// The talks' named lighting effects, each switchable in the march (CloudParams::effects.x) so that its
// contribution can be measured against the path-traced reference (cumulo fidelity).
#define CLOUD_EFFECT_SILVER_LINING 1u   // the forward HG lobe (off: the backward lobe alone)
#define CLOUD_EFFECT_DARK_EDGES 2u      // the dimensional profile in the multiple-scattering field (off: 1 inside cloud)
#define CLOUD_EFFECT_INNER_GLOW 4u      // the multiple-scattering field (off: no ms term)
#define CLOUD_EFFECT_LONG_SHADOWS 8u    // the light grid beyond the two marched light samples (off: those alone)
#define CLOUD_EFFECT_AMBIENT_DIRECTION 16u  // exp(-summed sky density) on the ambient (off: 1)
#define CLOUD_EFFECT_LIGHTNING_GLOW 32u  // the point lights' glow (off: none)
#define CLOUD_EFFECTS_ALL 63u

// Ablations (compile-time: the shader is built once per variant, so loops have no dead branches).
#define CLOUD_ABLATION_BASE 0            // uniform step over the clipped segment + 10-sample 256 m light march
#define CLOUD_ABLATION_VOXEL_LIGHTING 1  // base + light grid after two marched light samples
#define CLOUD_ABLATION_FULL 2            // + SDF and adaptive step

// Segments of the march (define SEGMENT): the 30 Hz single march, or the 40/60 Hz split.
#define CLOUD_SEGMENT_ALL 0
#define CLOUD_SEGMENT_NEAR 1  // [0, split) at half resolution
#define CLOUD_SEGMENT_FAR 2   // [split, end) at full resolution

// Weather coverage (issue 20): every voxel holds a coverage threshold (the recipe's per-edit "coverage",
// bake/recipe.h; the modeling NVDF's alpha, or coverage.nvdf on the BC1 path). Its cloud's presence at the
// weather's coverage c is saturate(1 + (c - threshold) / CLOUD_COVERAGE_RAMP): whole at c >= threshold, gone at
// c <= threshold - CLOUD_COVERAGE_RAMP, linear between (a transition, which blends c, thins a cloud smoothly).
// Threshold 0 is present at every coverage (the default). The profile is re-ranged like dissipation's, so a
// fading cloud shrinks from the outside in and an absent one has profile 0 everywhere.
#define CLOUD_COVERAGE_RAMP 0.2
// The bake's fair-weather field holds the clouds whose threshold is below this band; at a coverage of
// CLOUD_COVERAGE_BAND - CLOUD_COVERAGE_RAMP or less every other cloud is absent, and the march steps through
// the air by that field instead of the field of every cloud (CloudInstanceParams.weather.y = 1).
#define CLOUD_COVERAGE_BAND 0.6

struct CloudInstanceParams {
  mat4 world_to_asset;  // inverse of the instance transform
  vec4 bounds_min;      // xyz: asset bounds (the NVDF header's world box); w: uniform scale (world m per asset m)
  vec4 bounds_max;      // xyz; w: 1 / scale
  vec4 sun_dir;         // xyz: unit vector toward the sun in asset space; w: density multiplier
  vec4 sky_dir;         // xyz: unit vector up (world +Y) in asset space; w: dissipation 0..1
  vec4 wind_offset;     // xyz: noise scroll (asset metres), wind direction * speed * time; w: asset slot (0 or 1)
  vec4 weather;         // x: the weather's coverage 0..1 (CLOUD_COVERAGE_RAMP; 1 without a weather); y: 1 = march the air
                        // by the asset's fair-weather field (CLOUD_COVERAGE_BAND); z, w: unused
};
CUMULO_SHARED_SIZE(CloudInstanceParams, 160)

struct CloudParams {
  mat4 view_proj;       // world -> clip (reversed-Z: near 1, far 0)
  mat4 inv_view_proj;   // clip -> world
  mat4 prev_view_proj;  // last frame's view_proj (temporal reprojection)
  vec4 camera_pos;      // xyz: world (m); w: time (s)
  vec4 sun_dir;         // xyz: unit toward the sun (world); w: the slab's enclosed-air sky optical depth (0: none)
  vec4 sun_color;       // rgb: sun radiance scale (colour x illuminance, linear); w: the slab's lateral leak (0: none)
  vec4 ambient_color;   // rgb: sky ambient (linear); w: unused
  vec4 viewport;        // full resolution: width, height, 1/width, 1/height
  vec4 march;           // x: extinction per unit density (1/m), y: scattering albedo, z: transmittance limit, w: max steps
  vec4 steps;           // x: near/far split distance (200 m), y: animated-jitter distance (250 m), z: base uniform step (m), w: noise mip distance scale
  vec4 phase;           // x: forward HG g, y: backward HG g, z: forward lobe weight, w: multiple-scattering strength
  vec4 light;           // x: length of the first marched light sample (m), y: sky (ambient) optical-depth scale, z: base light march length (256 m), w: base light samples (10)
  vec4 misc;            // x: jitter scale, y: temporal blend (weight of the new frame), z: light-grid debug slice 0..1, w: 1 = history valid
  uvec4 frame;          // x: frame index, y: instance count, z: point-light count, w: debug view
  vec4 haze;            // aerial perspective of the composite: x fog density at sea level (1/m), y height falloff (1/m);
                        // z: 1 = the terrain's light depth map is bound (TERRAIN_SHADOW), w: its metres per unit depth
  vec4 sky_zenith;      // rgb: the sky straight up (the colour the haze tends to, with sky_horizon)
  vec4 sky_horizon;     // rgb: the sky at the horizon
  vec4 light_pos[CLOUD_MAX_POINT_LIGHTS];    // xyz: world position; w: radius (m)
  vec4 light_color[CLOUD_MAX_POINT_LIGHTS];  // rgb: colour x intensity; w: unused
  mat4 light_depth;     // world -> the key light's depth map NDC (render::LightDepth; TERRAIN_SHADOW)
  uvec4 effects;        // x: CLOUD_EFFECT_* bits of the lighting terms in effect (the march); y: bit 0 = other instances
                        // shadow an instance (light_grid_lookup.glsl); z, w (floats by their bits; MS_FIELD): the
                        // solved multiple scattering's weight against the slab's falloff, its strength over the slab's
  vec4 ms;              // the multiple-scattering field's attenuation (x od): x deep inside toward the sun (talk 0.05),
                        // y at the surface and away from the sun (talk 0.25); z: 1 = diffusion's falloff
                        // 1 / (1 + 0.75 (1 - g) od_own) instead (CloudSettings::ms_diffusion); w: with z, the
                        // Beer-Lambert coefficient of other clouds' optical depth on it (ms_other_cloud_attenuation)
  vec4 light_march;     // the marched light samples before the grid (voxel-lighting / full): x their count (the talk: 2),
                        // y each next one's length over the one before (the talk: 1), z their total length (m), where the
                        // grid takes over; the first one's length is light.x; w: the in-cloud step's growth
                        // cap (CloudSettings::step_growth; 1: the talk's step)
  vec4 slab;            // the slab's terms (0: off): x its incidence blend (CloudSettings::ms_incidence), y the cavity
                        // (ms_cavity), z the sky through the nearest surface (sky_side), w the forward lobe past the
                        // first order (ms_forward)
  vec4 ground_light;    // rgb: the ground's radiance per unit albedo under the sun and the sky, which the slab's ground
                        // bounce reflects into the clouds (the sun's irradiance x sin(elevation) / pi plus the sky's
                        // horizontal irradiance / pi); w: unused
  CloudInstanceParams instances[CLOUD_MAX_INSTANCES];
};
CUMULO_SHARED_SIZE(CloudParams, 1328)

// Push constants of light_grid_update.comp: one slab of one instance's grid per dispatch.
struct CloudLightGridPush {
  uvec4 region;  // x: instance, y: first z layer, z: layer count, w: unused (each shader's header says what it reads)
  vec4 grid;     // x: sun march steps, y: sky march steps, z: z layers per instance, w: unused
};
CUMULO_SHARED_SIZE(CloudLightGridPush, 32)

// Push constants of shadow_map.comp.
struct CloudShadowPush {
  vec4 plane;  // xy: world x, z of the map's corner; zw: its size (m)
  vec4 light;  // xyz: unit toward the key light (world); w: the plane's height (world y)
};
CUMULO_SHARED_SIZE(CloudShadowPush, 32)

// Push constants of march_render.comp and split_merge.comp.
struct CloudMarchPush {
  vec4 target;  // x, y: size of the image written (full resolution for the sub-sampled march), z, w: 1/size
  vec4 sub;     // reprojection (march_render.comp, reconstruct.comp): x block size B (1: every pixel), y, z: marched pixel in its block; w: unused
};
CUMULO_SHARED_SIZE(CloudMarchPush, 32)

// ---- Lightning bolts and rain (lightning_bolt.comp, rain.comp) -----------------------------------
#define CLOUD_MAX_BOLT_SEGMENTS 128  // two bolts of gameplay::kBoltMaxSegments
#define CLOUD_MAX_RAIN 4             // rain columns (one per precipitating instance)
#define CLOUD_BINDING_FX_PARAMS 0    // uniform CloudEffectsParams
#define CLOUD_BINDING_FX_DEPTH 1     // sampler2D: scene depth (reversed-Z)
#define CLOUD_BINDING_FX_CLOUDS 2    // sampler2D: cloud colour (a: transmittance)
#define CLOUD_BINDING_FX_CLOUD_DEPTH 3  // sampler2D: cloud depth (x: opacity-0.5 distance)
#define CLOUD_BINDING_FX_HDR 4       // image2D rgba16f: scene colour, read-modify-write

struct CloudEffectsParams {
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz; w: simulation time (s)
  vec4 viewport;       // width, height, 1/width, 1/height
  vec4 bolt;           // rgb: radiance of the channel's core; w: core radius (m)
  vec4 misc;           // x: angle of one pixel (rad), y: cloud outputs valid (1), z, w: unused
  uvec4 counts;        // x: bolt segments, y: rain columns
  vec4 seg_a[CLOUD_MAX_BOLT_SEGMENTS];  // xyz: segment start (world); w: brightness
  vec4 seg_b[CLOUD_MAX_BOLT_SEGMENTS];  // xyz: segment end
  vec4 rain_column[CLOUD_MAX_RAIN];     // xyz: centre at the cloud base (world); w: radius (m)
  vec4 rain_params[CLOUD_MAX_RAIN];     // x: intensity 0..1, y: bottom (world y), z, w: unused
  vec4 rain_light;                      // rgb: light scattered by the rain (sky ambient + some sun)
};
CUMULO_SHARED_SIZE(CloudEffectsParams, 4384)

// Push constants of lightning_bolt.comp: the screen rectangle dispatched (the bolts' bounds).
struct CloudEffectsPush {
  ivec4 rect;  // x, y: first pixel; z, w: size
};
CUMULO_SHARED_SIZE(CloudEffectsPush, 16)

// ---- Light shafts (light_shafts.comp, light_shafts_apply.comp) -------------------------------------
#define SHAFT_BINDING_PARAMS 0      // uniform CloudShaftParams
#define SHAFT_BINDING_DEPTH 1       // sampler2D: scene depth (reversed-Z)
#define SHAFT_BINDING_CLOUDS 2      // sampler2D: voxel cloud colour (a: transmittance)
#define SHAFT_BINDING_SKY 3         // sampler2D: the 2.5D sky's colour (a: transmittance), or a white 1x1
#define SHAFT_BINDING_OUT 4         // image2D r16f: shaft intensity (light_shafts.comp)
#define SHAFT_BINDING_SHAFTS 5      // sampler2D: shaft intensity (light_shafts_apply.comp)
#define SHAFT_BINDING_HDR 6         // image2D rgba16f: scene colour, read-modify-write
#define SHAFT_BINDING_CLOUD_DEPTH 7 // sampler2D: voxel cloud depth (x: opacity-0.5 distance)

struct CloudShaftParams {
  mat4 inv_view_proj;
  mat4 view_proj;
  vec4 camera_pos;  // xyz; w unused
  vec4 sun_dir;     // xyz toward the sun; w: cos of the highlight's angular radius
  vec4 sun_screen;  // xy: the sun's uv on screen (may lie outside 0..1); z: 1 = in front of the camera; w: samples
  vec4 mie;         // x: Mie g, y: strength, z: haze density (1/m at sea level), w: haze falloff (1/m)
  vec4 sun_color;   // rgb: sun illuminance (pi x radiance); w: decay per sample
  vec4 misc;        // x: sky distance (m), y: darkest fraction kept, z: blur length (fraction of the way to the sun), w unused
};
CUMULO_SHARED_SIZE(CloudShaftParams, 224)

CUMULO_SHARED_END

#endif
