// Parameters of the path-traced reference (modules/clouds/reference/reference_tracer.h), shared by C++ and
// GLSL. The tracer binds the real-time march's CloudParams (camera, sun, instances, extinction, albedo,
// phase constants) at CLOUD_BINDING_PARAMS, so both march exactly the same density field; this block adds
// what only the reference has: the bounce limit, the phase choice, the terrain heightfield, the sky
// environment and the analytic test medium.
#ifndef CUMULO_SHARED_REFERENCE_PARAMS_H
#define CUMULO_SHARED_REFERENCE_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

// Bindings (set 0, push descriptors); 0..3, 5, 10 are the march's (cloud_params.h).
#define REF_BINDING_PARAMS 14     // uniform ReferenceParams
#define REF_BINDING_MAJORANT 15   // sampler3D r16f/r32f: slot 0's majorant grid (max density per coarse cell)
#define REF_BINDING_MAJORANT_1 16 // sampler3D: slot 1's
#define REF_BINDING_MAJORANT_2 44 // sampler3D: slot 2's (CLOUD_BINDING_*_2 take 40..43)
#define REF_BINDING_TERRAIN 17    // sampler2D rgba32f: x height (world y), yzw albedo (linear)
#define REF_BINDING_ENV 18        // sampler2D rgba32f: sky radiance, latitude-longitude (ReferenceParams::env)
#define REF_BINDING_AERIAL 19     // sampler3D: the atmosphere's aerial-perspective froxels (REF_FLAG_AERIAL)
#define REF_BINDING_ACCUM 20      // image2D rgba32f: rgb sum of radiance, a sum of luminance^2
#define REF_BINDING_AUX 21        // image2D rgba32f: x sum of the view ray's cloud transmittance, y samples, z majorant violations
#define REF_BINDING_MODELING_IN 22  // majorant pass: sampler3D modeling NVDF being reduced
#define REF_BINDING_MAJORANT_OUT 23 // majorant pass: image3D r32f
#define REF_BINDING_HDR 24        // resolve: image2D rgba16f scene colour (written)
#define REF_LOCAL_SIZE 8

// Modeling voxels per majorant cell along each axis.
#define REF_MAJORANT_CELL 8

// ReferenceParams::flags.x bits.
#define REF_FLAG_SUN 1u        // next-event estimation toward the sun (CloudParams sun_dir / sun_color)
#define REF_FLAG_SKY 2u        // escaped paths gather the sky environment
#define REF_FLAG_TERRAIN 4u    // the heightfield is bound (opaque Lambertian surface)
#define REF_FLAG_AERIAL 8u     // the primary ray's first vertex is hazed with the aerial-perspective froxels
#define REF_FLAG_ANALYTIC 16u  // the medium is ReferenceParams::medium_* (tests), not the cloudscape
#define REF_FLAG_SCENE_DEPTH 32u  // the primary ray ends at the scene depth (the raster terrain) and lands on the heightfield there
#define REF_FLAG_OCEAN 64u     // a Lambertian plane at terrain.w beyond the heightfield

// Phase functions (ReferenceParams::settings.y).
#define REF_PHASE_CLOUD 0  // the real-time march's dual-lobe HG (CloudParams::phase)
#define REF_PHASE_MIE 1    // Jendersie & d'Eon 2023's approximate Mie (HG + Draine) for ReferenceParams::mie
#define REF_PHASE_ISOTROPIC 2

struct ReferenceParams {
  vec4 settings;       // x: max bounces, y: phase (REF_PHASE_*), z: first sample index of this dispatch, w: samples this dispatch
  uvec4 flags;         // x: REF_FLAG_* bits, y: seed, z: point lights traced (<= CloudParams frame.z), w: unused
  vec4 terrain;        // xy: world x, z of the heightfield's corner; zw: its size (m)
  vec4 terrain_range;  // x: lowest height, y: highest height, z: unused, w: ocean plane height (world y)
  vec4 ocean_albedo;   // rgb: albedo of the ocean plane; w: unused
  vec4 env;            // x: sky radiance scale; yzw unused (the environment texture is latitude-longitude)
  vec4 mie;            // approximate Mie: x g_HG, y g_Draine, z alpha, w Draine weight
  vec4 medium_min;     // analytic medium (REF_FLAG_ANALYTIC): box min (world); w: extinction (1/m)
  vec4 medium_max;     // box max; w: single-scattering albedo
  vec4 medium;         // x: majorant (1/m, >= extinction), y: uniform sky radiance (tests; < 0: the environment)
  vec4 light_scale;    // x: point-light intensity per unit CloudParams light colour (W/sr-like); yzw unused
};
CUMULO_SHARED_SIZE(ReferenceParams, 176)

// Push constants of reference_majorant.comp.
struct ReferenceMajorantPush {
  ivec4 cells;  // xyz: majorant grid size; w: unused
};
CUMULO_SHARED_SIZE(ReferenceMajorantPush, 16)

CUMULO_SHARED_END

#endif
