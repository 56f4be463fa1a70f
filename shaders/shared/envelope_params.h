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
#define ENV_BINDING_TERRAIN 11     // envelope_shadow.comp: sampler2D r32f, the terrain's height (world y) over EnvelopeShadowPush::terrain
#define ENV_BINDING_SHADOW_OUT 12  // envelope_shadow.comp, envelope_shadow_combine.comp: image2D r16f, the light's transmittance
#define ENV_BINDING_SHADOW_IN 13   // envelope_shadow_combine.comp: sampler2D, the envelope's transmittance (envelope_shadow.comp)
#define ENV_BINDING_VOXEL_SHADOW 14  // envelope_shadow_combine.comp: sampler2D, the voxel clouds' shadow map (shadow_map.comp)
#define ENV_BINDING_TERRAIN_DEPTH 15 // envelope_march.comp: sampler2D, the geometry's depth from the key light (render::LightDepth)
#define ENV_BINDING_VOXEL_SHADOW_MAP 16  // envelope_march.comp: sampler2D, the voxel clouds' shadow map (shadow_map.comp)
#define ENV_BINDING_REFERENCE_OFFSET 32  // reference_trace.comp: the density's bindings (0..5) + this
#define ENV_MAX_YIELD_BOXES 4      // voxel cloudscape boxes the envelope yields to (no cloud drawn twice)

struct EnvelopeParams {
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz world (m); w: time (s)
  vec4 sun_dir;        // xyz toward the key light; w: octave_light's diffused floor past the first order (0: the octaves)
  vec4 sun_color;      // rgb (as the voxel clouds'); w: the ground's albedo (octave_light)
  vec4 ambient_color;  // rgb: sky ambient; w: unused
  vec4 map;            // xy: world x, z of texel (0, 0)'s corner; z: texel size (m); w: texels per side
  vec4 heights;        // x: lowest bottom, y: highest top (world y); z: edge gradient width (m); w: density multiplier
  vec4 noise;          // x: base noise tile (m), y: detail noise tile (m), z: detail erosion 0..1, w: coverage multiplier
  vec4 wind;           // xyz: the noise's scroll (m, world); w: extinction per unit density (1/m)
  vec4 march;          // x: step inside the envelope (m), y: its growth per metre of distance, z: max steps, w: light sample length (m)
  vec4 stepping;       // x: 1 cone + distance step mapping, 0 fixed steps (for a reader: the pipeline's CONE_STEPPING decides); y: draw distance (m); z: single-scattering albedo (the voxel clouds'); w: segment start (m)
  vec4 phase;          // x: forward HG g, y: backward HG g, z: forward weight, w: multiple-scattering strength
  vec4 misc;           // x: segment end (m); y: ambient at the bottom / at the top; z: yield box count; w: yield fade (m)
  vec4 octaves;        // the slab presets' lighting (envelope_march.comp octave_light; x = 0: issue 24's terms): Wrenninge's
                       // x extinction a, y contribution b, z eccentricity c per octave; w: the dark edges' scale
  vec4 yield_min[ENV_MAX_YIELD_BOXES];  // xyz: world AABB of a voxel cloudscape (the envelope yields inside it)
  vec4 yield_max[ENV_MAX_YIELD_BOXES];
  mat4 light_depth;    // world -> the key light's depth map NDC (render::LightDepth)
  vec4 terrain;        // x: the light depth map's metres per unit depth; y: the voxel clouds' shadow map's plane (world
                       // y); z: the detail noise's mean fBm the light samples erode by (the slab presets; 0: none);
                       // w: unused
  vec4 voxel_shadow;   // the voxel clouds' shadow map: xy world x, z of its corner, zw its size (m)
  vec4 ground_light;   // rgb: the ground's radiance per unit albedo (as the voxel clouds' CloudParams::ground_light); w: unused
};
CUMULO_SHARED_SIZE(EnvelopeParams, 512)

// Push constants of envelope_shadow.comp: the key light's transmittance through the envelope, from where the light's
// ray leaves the envelope's top down to the first terrain it meets, on a horizontal plane (render::LightShadowMap).
struct EnvelopeShadowPush {
  vec4 plane;    // xy: world x, z of the map's corner; zw: its size (m)
  vec4 light;    // xyz: toward the light; w: the plane's height (world y)
  vec4 terrain;  // xy: world x, z of the terrain square's corner; z: its side (m); w: the step along the light (m)
};
CUMULO_SHARED_SIZE(EnvelopeShadowPush, 48)

// Push constants of envelope_shadow_combine.comp: the envelope's map times the voxel clouds' (one map for the scene).
struct EnvelopeShadowCombinePush {
  vec4 plane;        // the combined map: xy corner, zw size (m)
  vec4 light;        // xyz: toward the light; w: the plane's height (world y), the envelope map's too
  vec4 envelope;     // the envelope's map on the same plane: xy corner, zw size
  vec4 voxel_plane;  // the voxel clouds' map: xy corner, zw size
  vec4 voxel;        // x: its plane's height (world y); y: 1 when bound
};
CUMULO_SHARED_SIZE(EnvelopeShadowCombinePush, 80)

CUMULO_SHARED_END

#endif
