// Parameters of the weather-driven 2.5D sky (modules/clouds/render/sky_layer.h; 2015 talk, seed 004:
// the spherical shell, cloud types, the 2D layers above, reprojection; 2017, seed 001: the weather map
// and the 2.5D ray-march), shared by C++ and GLSL. One block per frame slot.
#ifndef CUMULO_SHARED_SKY_LAYER_PARAMS_H
#define CUMULO_SHARED_SKY_LAYER_PARAMS_H
#include "shared/common.h"

CUMULO_SHARED_BEGIN

// sky_layer.comp (set 0, push descriptors; CloudMarchPush as push constants)
#define SKY_BINDING_PARAMS 0       // uniform SkyLayerParams
#define SKY_BINDING_CLOUD_MAP 1    // sampler2D rgba8: R coverage, G precipitation, B cloud type (tiling, drifting)
#define SKY_BINDING_BASE_NOISE 2   // sampler3D rgba8: R Perlin-Worley, G/B/A Worley fBm (128^3)
#define SKY_BINDING_DETAIL_NOISE 3 // sampler3D rgba8: Worley fBm at 3 frequencies (32^3)
#define SKY_BINDING_CURL 4         // sampler3D rgba8, depth 1: 2D curl noise (0.5 = no distortion)
#define SKY_BINDING_SCENE_DEPTH 5  // sampler2D: scene depth (reversed-Z)
#define SKY_BINDING_OUT_COLOR 6    // image2D rgba16f: rgb radiance, a transmittance
#define SKY_BINDING_OUT_DEPTH 7    // image2D rgba32f: x opacity-0.5 distance (1e6: none), y steps
#define SKY_MAX_YIELD_BOXES 4      // voxel cloudscape boxes the layer yields to
#define SKY_BINDING_PROBE_POINTS 8 // sky_layer_probe.comp: vec4 world points
#define SKY_BINDING_PROBE_OUT 9    // sky_layer_probe.comp: float densities
// sky_layer.comp, VOXEL_OCCLUSION 1: this frame's voxel clouds (where they hide the shell the layer is not marched)
// and the layer's last reconstruction (what such a pixel keeps)
#define SKY_BINDING_VOXEL_COLOR 10  // sampler2D rgba16f: a transmittance
#define SKY_BINDING_VOXEL_DEPTH 11  // sampler2D rgba32f: x opacity-0.5 distance
#define SKY_BINDING_HISTORY 12      // sampler2D rgba16f: the layer's last frame

struct SkyLayerParams {
  mat4 inv_view_proj;
  vec4 camera_pos;     // xyz world (m); w: time (s)
  vec4 sun_dir;        // xyz toward the key light; w: where the layer begins for this camera (m; SkyLayerFrame::near_fade_m)
  vec4 sun_color;      // rgb: the same sun as the voxel clouds (pi x Lambertian radiance); w: unused
  vec4 ambient_color;  // rgb: sky ambient at the layer's top; w: unused
  vec4 shell;          // x: inner altitude (m above sea level), y: outer, z: planet radius (m), w: max draw distance (m)
  vec4 weather;        // x: coverage 0..1, y: cloud type 0..1, z: precipitation 0..1, w: anvil bias 0..1
  vec4 wind;           // xy: cloud-map drift (m, world x, z), z: height skew 0..1, w: noise scroll (m)
  vec4 wind_dir;       // xyz: unit wind direction (world); w: cloud-map size (m, one tile)
  vec4 shape;          // x: base noise tile (m), y: detail noise tile (m), z: curl distortion (m), w: detail erosion 0..1
  vec4 horizon;        // x: distance where the cumulus bias starts (m), y: where it is full, z: biased coverage, w: biased type
  vec4 march;          // x: extinction per unit density (1/m), y: min steps, z: max steps, w: light sample length (m)
  vec4 phase;          // x: forward HG g, y: backward HG g, z: forward weight, w: multiple-scattering strength
  vec4 high;           // x: high-layer (cirrus/alto) coverage 0..1, y: altitude (m), z: tile (m), w: opacity scale
  vec4 high_scroll;    // xy: cirrus drift (m), zw: alto drift (m)
  vec4 misc;           // x: yield fade (m, outside each box's footprint), y: yield box count, z: jitter frame, w: vertical yield fade (m, above / below a box)
  vec4 yield_min[SKY_MAX_YIELD_BOXES];  // xyz: world AABB min of a voxel cloudscape; w unused
  vec4 yield_max[SKY_MAX_YIELD_BOXES];
  mat4 prev_view_proj;  // last frame's world -> clip (VOXEL_OCCLUSION: a hidden pixel keeps its last value)
};
CUMULO_SHARED_SIZE(SkyLayerParams, 496)

CUMULO_SHARED_END

#endif
