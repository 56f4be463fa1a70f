// Parameters of the Envelope method's orographic clouds (issue 24; modules/clouds/render/envelope_layer.h),
// shared by C++ and GLSL. One block per frame slot.
#ifndef CUMULO_SHARED_ENVELOPE_PARAMS_H
#define CUMULO_SHARED_ENVELOPE_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

// envelope_march.comp and envelope_probe.comp (set 0, push descriptors; CloudMarchPush as push constants)
#define ENV_BINDING_PARAMS 0       // uniform EnvelopeParams
#define ENV_BINDING_SHAPE 1        // sampler2D rgba32f, bilinear: bottom, top (world y), coverage, detail type
#define ENV_BINDING_STEPS 2        // sampler2D rgba32f, texelFetch: conservative top, bottom, top and bottom cone ratios
#define ENV_BINDING_AUX 3          // sampler2D rgba32f: x distance step (m, texelFetch), y edge distance (m, bilinear), zw the cones' apexes (texelFetch)
#define ENV_BINDING_BASE_NOISE 4   // sampler3D rgba8: R Perlin-Worley, G/B/A Worley fBm (the 2.5D sky's, 128^3)
#define ENV_BINDING_DETAIL_NOISE 5 // sampler3D rgba8: Worley fBm at 3 frequencies (32^3)
#define ENV_BINDING_SCENE_DEPTH 6  // sampler2D: scene depth (reversed-Z)
#define ENV_BINDING_OUT_COLOR 7    // image2D rgba16f: rgb radiance, a transmittance
#define ENV_BINDING_OUT_DEPTH 8    // image2D rgba32f: x opacity-0.5 distance (1e6: none), y samples, z the ray's end, w steps taken
#define ENV_BINDING_PROBE_POINTS 9 // envelope_probe.comp: vec4 world points
#define ENV_BINDING_PROBE_OUT 10   // envelope_probe.comp: vec4 (density, profile, height fraction, edge gradient)
#define ENV_MAX_YIELD_BOXES 4      // voxel cloudscape boxes the envelope yields to (no cloud drawn twice)

struct EnvelopeParams {
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz world (m); w: time (s)
  vec4 sun_dir;        // xyz toward the key light; w: unused
  vec4 sun_color;      // rgb (as the voxel clouds'); w: unused
  vec4 ambient_color;  // rgb: sky ambient; w: unused
  vec4 map;            // xy: world x, z of texel (0, 0)'s corner; z: texel size (m); w: texels per side
  vec4 heights;        // x: lowest bottom, y: highest top (world y); z: edge gradient width (m); w: density multiplier
  vec4 noise;          // x: base noise tile (m), y: detail noise tile (m), z: detail erosion 0..1, w: coverage multiplier
  vec4 wind;           // xyz: the noise's scroll (m, world); w: extinction per unit density (1/m)
  vec4 march;          // x: step inside the envelope (m), y: its growth per metre of distance, z: max steps, w: light sample length (m)
  vec4 stepping;       // x: 1 cone + distance step mapping, 0 fixed steps (for a reader: the pipeline's CONE_STEPPING decides); y: draw distance (m); z: unused; w: segment start (m)
  vec4 phase;          // x: forward HG g, y: backward HG g, z: forward weight, w: multiple-scattering strength
  vec4 misc;           // x: segment end (m); y: ambient at the bottom / at the top; z: yield box count; w: yield fade (m)
  vec4 yield_min[ENV_MAX_YIELD_BOXES];  // xyz: world AABB of a voxel cloudscape (the envelope yields inside it)
  vec4 yield_max[ENV_MAX_YIELD_BOXES];
};
CUMULO_SHARED_SIZE(EnvelopeParams, 384)

CUMULO_SHARED_END

#endif
