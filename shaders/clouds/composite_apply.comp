#version 450
// Cloud composite over the scene colour, before tonemap (issue 8 pass 5; DESIGN.md "composite"):
// hdr = hdr * transmittance + in-scattered radiance. With no cloud (transmittance exactly 1, radiance
// exactly 0) the scene is left bit-exact. The sun and ambient colours were already applied by the
// march (CloudFrameInputs). Aerial perspective (2017 talk: the clouds blend into the distance) at the
// cloud's half-opacity depth (hazed() below): the atmosphere's froxels when bound (AERIAL 1), else the
// terrain's height fog (sky_common.glsl's fog_amount) toward the sky's gradient colour:
//   hdr = hdr * T + (1 - f) * radiance + f * (1 - T) * sky.
// Debug views (P.frame.w; DEBUG_VIEWS 1): profile and split arrive opaque from the march/merge (alpha 0); steps maps
// the march's step count (depth image y) to a blue..red heat map over P.march.w steps; light-grid shows
// a horizontal slice of instance 0's grid at height P.misc.z (0..1): red = sun transmittance
// exp(-extinction * summed density), green = the same toward the sky.
// SKY_LAYER 1: the 2.5D sky (sky_layer.comp, half resolution, bilinear) is composited too, each layer
// hazed at its own half-opacity depth, the nearer one over the farther (the voxel clouds stand in front
// of the shell's clouds from the ground; from above, the shell's may be nearer). Where the scene's
// geometry is nearer than the sky's depth, the upsampled sky is dropped (no halo around terrain).
// ENVELOPE 1: the Envelope method's orographic clouds (envelope_march.comp; at most the output's size, upsampled
// depth-aware against the scene's depth) are a third layer: the three are composited farthest first by their
// half-opacity depths.
// UPSAMPLE 1: the voxel clouds were marched below the output's size (dynamic resolution): upsampled
// depth-aware against the scene's depth (depth_aware_upsample.glsl).
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_CLOUDS) uniform sampler2D clouds_tex;
layout(set = 0, binding = CLOUD_BINDING_HDR, rgba16f) uniform image2D hdr;
layout(set = 0, binding = CLOUD_BINDING_DEBUG_GRID) uniform sampler3D debug_grid;
layout(set = 0, binding = CLOUD_BINDING_CLOUD_DEPTH) uniform sampler2D cloud_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };
#ifndef SKY_LAYER
#define SKY_LAYER 0
#endif
#ifndef AERIAL
#define AERIAL 0
#endif
#if AERIAL
#include "engine/atmosphere_common.glsl"
layout(set = 0, binding = CLOUD_BINDING_AERIAL) uniform sampler3D aerial_tex;
#endif
#ifndef UPSAMPLE
#define UPSAMPLE 0
#endif
#ifndef DEBUG_VIEWS
#define DEBUG_VIEWS 0  // 1: the steps and light-grid views (compiled out otherwise: an unused branch costs on a CPU device)
#endif
#if SKY_LAYER
layout(set = 0, binding = CLOUD_BINDING_SKY_COLOR) uniform sampler2D sky_tex;
layout(set = 0, binding = CLOUD_BINDING_SKY_DEPTH) uniform sampler2D sky_depth_tex;
#endif
#ifndef ENVELOPE
#define ENVELOPE 0
#endif
#if ENVELOPE
layout(set = 0, binding = CLOUD_BINDING_ENVELOPE_COLOR) uniform sampler2D envelope_tex;
layout(set = 0, binding = CLOUD_BINDING_ENVELOPE_DEPTH) uniform sampler2D envelope_depth_tex;
#endif
#ifndef ENVELOPE_UPSAMPLE
#define ENVELOPE_UPSAMPLE 0  // 1: the envelope's layer is below the output's size (bilinear, as the 2.5D sky)
#endif
#ifndef ENVELOPE_SPLIT
#define ENVELOPE_SPLIT 0  // 1: the envelope's near pass (half its resolution) merges over its far pass here
#endif
#if ENVELOPE_SPLIT
layout(set = 0, binding = CLOUD_BINDING_ENVELOPE_NEAR_COLOR) uniform sampler2D envelope_near_tex;
layout(set = 0, binding = CLOUD_BINDING_ENVELOPE_NEAR_DEPTH) uniform sampler2D envelope_near_depth_tex;
#endif
#if SKY_LAYER || UPSAMPLE || ENVELOPE
layout(set = 0, binding = CLOUD_BINDING_SCENE_DEPTH_COMPOSITE) uniform sampler2D scene_depth_tex;
#endif
#if UPSAMPLE || ENVELOPE
#include "clouds/depth_aware_upsample.glsl"
#endif

vec3 heat(float x) {
  x = clamp(x, 0.0, 1.0);
  return clamp(vec3(1.5 - abs(4.0 * x - 3.0), 1.5 - abs(4.0 * x - 2.0), 1.5 - abs(4.0 * x - 1.0)), 0.0, 1.0);
}

// The terrain's haze (sky_common.glsl fog_amount, sky_gradient without the sun's glow) at distance `dist`.
float haze_amount(vec3 ro, vec3 dir, float dist) {
  float density = P.haze.x, falloff = max(P.haze.y, 1e-6);
  float dy = dir.y * dist;
  float integral = abs(dy) > 1e-3 ? (exp(-falloff * ro.y) - exp(-falloff * (ro.y + dy))) / (falloff * dir.y)
                                  : dist * exp(-falloff * ro.y);
  return 1.0 - exp(-density * max(integral, 0.0));
}
vec3 haze_colour(vec3 dir) { return mix(P.sky_horizon.rgb, P.sky_zenith.rgb, pow(clamp(dir.y, 0.0, 1.0), 0.5)); }

// A cloud layer (radiance, transmittance) seen through the air in front of it, at its half-opacity depth:
// AERIAL 1, the atmosphere's froxels (Hillaire 2020: radiance x the air's transmittance + the air's
// in-scattering where the cloud hides what lies behind); else the terrain's height fog toward the sky.
vec3 hazed(vec4 layer, float depth, vec3 ro, vec3 dir, vec2 uv) {
  if (layer.a >= 1.0 || depth >= 1e5) return layer.rgb;
#if AERIAL
  vec4 ap = atm_aerial_lookup(aerial_tex, uv, depth * 0.001);
  return layer.rgb * ap.a + ap.rgb * (1.0 - layer.a);
#else
  if (P.haze.x <= 0.0) return layer.rgb;
  float f = haze_amount(ro, dir, depth);
  return (1.0 - f) * layer.rgb + f * (1.0 - layer.a) * haze_colour(dir);
#endif
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec4 scene = imageLoad(hdr, pixel);
  vec3 ro = P.camera_pos.xyz;
  vec3 dir = view_ray_dir(P.inv_view_proj, uv * 2.0 - 1.0, ro);
#if SKY_LAYER || UPSAMPLE || ENVELOPE
  float d = textureLod(scene_depth_tex, uv, 0.0).r;
  float t_scene = 1e30;
  if (d > 0.0) {
    vec4 w = P.inv_view_proj * vec4(uv * 2.0 - 1.0, d, 1.0);
    t_scene = distance(w.xyz / w.w, ro);
  }
#endif
#if UPSAMPLE
  vec4 c, cd;
  depth_aware_upsample(clouds_tex, cloud_depth, pixel, size, min(t_scene, 1e6), c, cd);
#else
  vec4 c = texelFetch(clouds_tex, pixel, 0);
  vec4 cd = texelFetch(cloud_depth, pixel, 0);
#endif
  float depth50 = cd.x;
  // Each layer as (radiance after haze, transmittance), hazed at its own depth.
  vec3 voxel_rgb = hazed(c, depth50, ro, dir, uv);
#if ENVELOPE
  // Three layers (radiance after haze, transmittance) composited farthest first by their half-opacity depths: a
  // compare-and-swap network on the three (an absent layer is (0, 1), which commutes with anything); on a tie the
  // 2.5D sky lies behind the voxel clouds (as below) and the envelope behind both.
  vec4 lv = vec4(voxel_rgb, c.a), ls = vec4(0.0, 0.0, 0.0, 1.0);
  float dv = depth50, ds = -1.0;
#if SKY_LAYER
  vec4 s = textureLod(sky_tex, uv, 0.0);
  float sky50 = textureLod(sky_depth_tex, uv, 0.0).x;
  if (s.a < 1.0 && sky50 < t_scene) {
    ls = vec4(hazed(s, min(sky50, 9e4), ro, dir, uv), s.a);
    ds = sky50;
    // A block whose marched pixel missed has no depth ("at infinity") while its reprojected pixels show cloud: that
    // cloud is the near field, so it stays in front of the shell instead of dropping behind it block by block.
    if (dv >= 1e5 && c.a < 1.0) dv = 0.999 * ds;
  }
#endif
  vec4 e;
  float de;
#if ENVELOPE_SPLIT
  vec4 ed, en, end_;
  depth_aware_upsample(envelope_tex, envelope_depth_tex, pixel, size, min(t_scene, 1e6), e, ed);
  // The near pass's rays end at the split (the voxel clouds' distance, P.steps.x, which the envelope shares).
  depth_aware_upsample(envelope_near_tex, envelope_near_depth_tex, pixel, size, min(t_scene, P.steps.x), en, end_);
  merge_near_over_far(en, end_, e, ed, e, ed);
  de = ed.x;
#elif ENVELOPE_UPSAMPLE
  e = textureLod(envelope_tex, uv, 0.0);  // half size (a CPU device): bilinear, as the 2.5D sky
  de = textureLod(envelope_depth_tex, uv, 0.0).x;
#else
  e = texelFetch(envelope_tex, pixel, 0);
  de = texelFetch(envelope_depth_tex, pixel, 0).x;
#endif
  vec4 le = vec4(hazed(e, min(de, 9e4), ro, dir, uv), e.a);
  // x1 farthest .. x3 nearest.
  vec4 x1 = lv, x2 = ls, x3 = le;
  float d1 = dv, d2 = ds, d3 = de;
  if (d2 >= d1) { vec4 t = x1; x1 = x2; x2 = t; float u = d1; d1 = d2; d2 = u; }
  if (d3 >= d2) { vec4 t = x2; x2 = x3; x3 = t; float u = d2; d2 = d3; d3 = u; }
  if (d2 >= d1) { vec4 t = x1; x1 = x2; x2 = t; float u = d1; d1 = d2; d2 = u; }
  vec3 rgb = ((scene.rgb * x1.a + x1.rgb) * x2.a + x2.rgb) * x3.a + x3.rgb;
#else
  vec3 rgb = scene.rgb * c.a + voxel_rgb;
#if SKY_LAYER
  vec4 s = textureLod(sky_tex, uv, 0.0);
  float sky50 = textureLod(sky_depth_tex, uv, 0.0).x;
  if (s.a < 1.0 && sky50 < t_scene) {
    vec3 sky_rgb = hazed(s, min(sky50, 9e4), ro, dir, uv);
    // (a block with no depth: its reprojected cloud in front, as above)
    if (sky50 >= depth50 || depth50 >= 1e5) rgb = (scene.rgb * s.a + sky_rgb) * c.a + voxel_rgb;  // the shell behind
    else rgb = (scene.rgb * c.a + voxel_rgb) * s.a + sky_rgb;
  }
#endif
#endif
#if DEBUG_VIEWS
  uint view = P.frame.w;
  if (view == CLOUD_DEBUG_STEPS) {
    rgb = heat(cd.y / max(P.march.w, 1.0));
  } else if (view == CLOUD_DEBUG_LIGHT_GRID) {
    vec2 g = textureLod(debug_grid, vec3(uv.x, P.misc.z, uv.y / float(max(P.frame.y, 1u))), 0.0).xy;
    rgb = vec3(exp(-g.x * P.march.x), exp(-g.y * P.march.x), 0.0);
  }
#endif
  imageStore(hdr, pixel, vec4(rgb, scene.a));
}
