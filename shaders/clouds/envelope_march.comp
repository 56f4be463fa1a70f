#version 450
// The Envelope method's ray-march (issue 24; seed 000 "Cone Step Mapping + Distance Step Mapping"): orographic
// clouds from 2D data (envelope_density.glsl), flight-capable, so samples must gather around the clouds near the
// camera rather than fill the empty air.
//
// CONE_STEPPING 1 (the talk's): outside the envelope a sample never reads the density. At a point above the
// conservative top of its texel's 3x3 (the cone's apex, envelope_maps.h), the upward cone rooted there (the baked
// ratio: horizontal distance per metre of height, Dummer 2006) holds no cloud, so the ray may go to where it leaves it:
//   t = ratio * h / (|d.xz| - ratio * d.y)   (h: height above the top; never leaves when the denominator <= 0)
// and the same under the bottom with the downward cone. The distance map adds the horizontal distance to the
// footprint (t = distance / |d.xz|). The largest of the three is safe (each keeps the ray out of a set that holds the
// envelope). Inside a texel's column between the bottom and the top the march takes the small step and samples.
// CONE_STEPPING 0: the small step everywhere in the envelope's box (the talk's "before").
//
// Lighting, a term of its own (not the voxel clouds' light grid: these clouds span the islands, far beyond any
// cloudscape's grid, and change only by the noise's scroll): Beer-Lambert over four light samples toward the sun
// (lengths 1, 2, 4, 8 x E.march.w, through the density without the high-frequency erosion) times the voxel clouds'
// dual-lobe phase; a multiple-scattering term (exp(-od / 2) x strength x 0.5 / 4 pi: the 2.5D sky's exp(-od / 4) left
// the thick envelope clouds evenly white); the sky ambient,
// growing with the height in the envelope (issue 24's model, kept for the talk, tuned and diffusion presets). With the
// slab presets (issue 21) octave_light instead. Integrated the energy-conserving way (Hillaire 2016).
// The talk "did away with temporal upscaling" for these clouds: on a GPU every pixel is marched every frame and the
// jitter is fixed per pixel. On a CPU device the far pass marches one pixel of each BxB block a frame (CloudMarchPush
// sub) and reconstruct.comp reprojects the rest, as the voxel clouds' far segment does (EnvelopeMarchSettings).
// The stretch of the ray marched: [E.stepping.w, E.misc.x) (the 40/60 Hz split's near and far passes).
// The sun's light passes the terrain and the voxel clouds above (issue 21: the path tracer's does; before, the sample
// level's bank at the end in the hero cloud's shadow read 2-3x too bright). Both maps are always bound: without one
// this frame, a stand-in that hides nothing (envelope_layer.cpp).
#extension GL_GOOGLE_include_directive : require
#include "clouds/envelope_density.glsl"
#include "shared/cloud_params.h"
#include "engine/view_ray.glsl"
#include "engine/runtime_uniform.glsl"

#ifndef CONE_STEPPING
#define CONE_STEPPING 1
#endif

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = ENV_BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = ENV_BINDING_OUT_COLOR, rgba16f) uniform writeonly image2D out_color;
layout(set = 0, binding = ENV_BINDING_OUT_DEPTH, rgba32f) uniform writeonly image2D out_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };

layout(set = 0, binding = ENV_BINDING_TERRAIN_DEPTH) uniform sampler2D terrain_depth_tex;
layout(set = 0, binding = ENV_BINDING_VOXEL_SHADOW_MAP) uniform sampler2D voxel_shadow_tex;

// The terrain between a sample and the sun (the voxel clouds' terrain_visibility, issue 10): the key light's depth
// map, the shadow's edge softened over 40 m of depth.
float terrain_visibility(vec3 world) {
  vec4 c = E.light_depth * vec4(world, 1.0);
  vec3 n = c.xyz / c.w;
  vec2 uv = n.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || n.z <= 0.0) return 1.0;
  float occluder = textureLod(terrain_depth_tex, uv, 0.0).r;
  return saturate(1.0 - (n.z - occluder) * E.terrain.x / 40.0);
}

// The voxel clouds above: their shadow map's transmittance (shadow_map.comp), on its plane under their boxes, where
// the ray toward the sun crosses it.
float voxel_transmittance(vec3 p, vec3 l) {
  if (l.y + runtime_zero() <= 1e-3) return 1.0;  // (runtime_uniform.glsl: the sun alone decides it)
  vec2 xz = p.xz + l.xz * ((E.terrain.y - p.y) / l.y);
  vec2 uv = (xz - E.voxel_shadow.xy) / E.voxel_shadow.zw;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  return textureLod(voxel_shadow_tex, uv, 0.0).r;
}

// The ray's stretch inside the envelope's box ([map extent] x [lowest bottom, highest top]); x >= y: none.
vec2 box_segment(vec3 ro, vec3 rd) {
  vec3 lo = vec3(E.map.x, E.heights.x, E.map.y);
  vec3 hi = vec3(E.map.x + E.map.z * E.map.w, E.heights.y, E.map.y + E.map.z * E.map.w);
  vec3 inv = 1.0 / rd;
  vec3 a = (lo - ro) * inv, b = (hi - ro) * inv;
  vec3 tmin = min(a, b), tmax = max(a, b);
  return vec2(max(max(tmin.x, tmin.y), max(tmin.z, 0.0)), min(min(tmax.x, tmax.y), tmax.z));
}

// Where the ray leaves the cone of `ratio` rooted `h` metres below (above) it; `up`: the ray's vertical component away
// from the root (d.y above a top, -d.y under a bottom).
float cone_step(float h, float ratio, float horizontal, float up) {
  float denom = horizontal - ratio * up;
  return denom > 1e-6 ? ratio * h / denom : 1e9;
}

// The light samples skip the detail noise (a fetch each), but the view ray's density is eroded by it: without the
// erosion they see more cloud toward the sun than the ray does, and the path tracer, which traces the eroded density
// both ways, lights a bank's underside a quarter brighter (docs/fidelity/envelope_lighting.md, session 57). With the
// slab presets they erode by the detail's mean fBm (E.terrain.z; 0: not at all, the talk's), as
// envelope_density.glsl erodes by the sampled one.
float light_optical_depth(vec3 p, vec3 l) {
  float od = 0.0, t = 0.0, len = E.march.w;
  for (int k = 0; k < 4; ++k) {
    float d = envelope_sample(p + l * (t + 0.5 * len), false).density / max(E.heights.w, 1e-6);
    od += envelope_erode(d, E.terrain.z) * E.heights.w * len;
    t += len;
    len *= 2.0;
  }
  return od * E.wind.w;
}

// The envelope's lighting with the voxel clouds' slab presets (issue 21; E.octaves.x > 0). The sun's light, direct and
// multiply scattered, as Wrenninge's octaves (2015): sum over n < 4 of b^n exp(-a^n od) p(mu; c^n g), (a, b, c) =
// E.octaves.xyz: the first orders keep the phase's forward lobe and see through more of the cloud.
// Here the light grid's depths the slab needs are not there; the octaves measured better against the path tracer on
// the envelope's own views than the slab's falloff with the column's depths (docs/fidelity/envelope_lighting.md).
// The sky and the ground bounce are the slab's, through the envelope's column above and below the sample (the shape
// map's bottom and top) at half this sample's extinction (the profile's gradients thin it toward both ends):
// the upper hemisphere's phase-weighted share of the sky, occluded by the column above; the sky's light diffused in,
// darkened at the edges by the optical depth to the nearest of the column's surfaces (E.octaves.w, the voxel clouds'
// edge scale); the ground's (albedo E.sun_color.w) from the lower hemisphere through the column below.
vec3 octave_light(vec3 p, vec3 rd, vec3 l, float mu, float od_sun, float sun_visible, EnvelopeSample es) {
  vec3 sun = vec3(0.0);
  float a = 1.0, b = 1.0, c = 1.0;
  float orders = 0.0, ph_last = 0.0;
  for (int n = 0; n < 4; ++n) {
    float ph = mix(henyey_greenstein(mu, c * E.phase.y), henyey_greenstein(mu, c * E.phase.x), E.phase.z);
    if (n == 0) sun += E.sun_color.rgb * (exp(-od_sun) * ph);
    else orders += b * exp(-a * od_sun) * ph;
    ph_last = ph;
    a *= E.octaves.x, b *= E.octaves.y, c *= E.octaves.z;
  }
  // Past the first order, at least diffusion's transmission through the optical depth toward the sun (E.sun_dir.w x
  // 1 / (1 + 0.75 (1 - g) od)): the octaves' exp(-a^n od) falls off far faster in a thick bank, diffusion's is what a
  // thick slab passes (its last octave's phase: the orders past the octaves are as isotropic).
  float diffused = E.sun_dir.w * ph_last / (1.0 + 0.75 * (1.0 - mix(E.phase.y, E.phase.x, E.phase.z)) * od_sun);
  vec2 uv = env_uv(p.xz);
  vec4 shape = textureLod(shape_tex, uv, 0.0);
  float edge_m = textureLod(aux_tex, uv, 0.0).y;
  float sigma = 0.5 * es.density * E.wind.w;
  float below = max(p.y - shape.x, 0.0), above = max(shape.y - p.y, 0.0);
  float tau_away = sigma * min(below / max(l.y, 0.2), 4.0 * max(below, edge_m));
  float tau_up = sigma * above;
  float g = mix(E.phase.y, E.phase.x, E.phase.z);  // the phase's mean cosine
  float r = 1.0 - g;
  float edge = 1.0 - exp(-E.octaves.w * sigma * min(min(below, above), edge_m));
  // The orders past the first need cloud around the point to scatter in: near a surface most of the light escapes
  // first, so they take the dark edges' in-scatter probability, as the voxel clouds' multiple scattering does.
  sun += E.sun_color.rgb * (max(orders, diffused) * edge);
  sun *= sun_visible;
  float sky_share = saturate(0.5 + 0.75 * g * rd.y);
  vec3 light_in = sun + E.ambient_color.rgb * (sky_share * exp(-tau_up) + edge * E.phase.w * 0.25 / (1.0 + 0.75 * r * tau_up));
  light_in += E.ground_light.rgb *
              (E.sun_color.w * (1.0 - sky_share) / (1.0 + 0.75 * r * tau_away));
  return light_in;
}

void main() {
  // pc.sub.x = B > 1: one pixel of each BxB block (at sub.yz in it), written at the block's texel (reconstruct.comp
  // rebuilds the rest from the last frame's).
  ivec2 block = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  int B = max(runtime_int(pc.sub.x), 1);
  if (any(greaterThanEqual(block * B, size))) return;
  ivec2 pixel = min(block * B + runtime_ivec2(pc.sub.yz), size - 1);
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = E.camera_pos.xyz;
  vec3 rd = view_ray_dir(E.inv_view_proj, ndc, ro);
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_scene = 1e6;
  if (d > 0.0) {
    vec4 w = E.inv_view_proj * vec4(ndc, d, 1.0);
    t_scene = min(distance(w.xyz / w.w, ro), 1e6);
  }
  vec2 seg = box_segment(ro, rd);
  seg.x = max(seg.x, E.stepping.w);
  seg.y = min(min(seg.y, t_scene), min(E.misc.x, E.stepping.y));

  vec3 radiance = vec3(0.0);
  float transmittance = 1.0, depth50 = 1e6, samples = 0.0, steps = 0.0;
  vec3 l = normalize(E.sun_dir.xyz);
  float mu = dot(rd, l);
  float phase = mix(henyey_greenstein(mu, E.phase.y), henyey_greenstein(mu, E.phase.x), E.phase.z);
  float horizontal = length(rd.xz);
  int max_steps = runtime_int(E.march.z);
  float t = seg.x + E.march.x * pixel_hash(vec2(pixel), 0u);
  for (int i = 0; i < max_steps && t < seg.y && transmittance > 0.01; ++i) {
    steps += 1.0;
    vec3 p = ro + rd * t;
    float dt = E.march.x + E.march.y * t;  // the small step, growing with the distance
#if CONE_STEPPING
    vec4 s = texelFetch(steps_tex, env_texel(p.xz), 0);
    if (p.y > s.x || p.y < s.y) {
      vec4 a = texelFetch(aux_tex, env_texel(p.xz), 0);
      float jump = 0.0;
      if (p.y > a.z) jump = cone_step(p.y - a.z, s.z, horizontal, rd.y);
      if (p.y < a.w) jump = max(jump, cone_step(a.w - p.y, s.w, horizontal, -rd.y));
      if (horizontal > 1e-4) jump = max(jump, a.x / horizontal);
      t += max(jump, dt);  // never shorter than the small step: never more steps than the fixed march
      continue;
    }
#endif
    EnvelopeSample es = envelope_sample(p, true);
    samples += 1.0;
    if (es.density > 0.0) {
      float od = light_optical_depth(p, l);
      vec3 light_in;
      if (E.octaves.x + runtime_zero() > 0.0) {  // (runtime_uniform.glsl: lavapipe would inline it)
        light_in = octave_light(p, rd, l, mu, od, terrain_visibility(p) * voxel_transmittance(p, l), es);
      } else {
        light_in = E.sun_color.rgb * (terrain_visibility(p) * voxel_transmittance(p, l) * (exp(-od) * phase + E.phase.w * exp(-od * 0.5) * 0.5 / (4.0 * kPi)));
        light_in += E.ambient_color.rgb * mix(E.misc.y, 1.0, es.hf);
      }
      float sigma_t = max(es.density * E.wind.w, 1e-7);
      float tr = exp(-sigma_t * dt);
      vec3 s_in = light_in * (sigma_t * E.stepping.z);
      radiance += transmittance * (s_in - s_in * tr) / sigma_t;
      float before = transmittance;
      transmittance *= tr;
      if (before >= 0.5 && transmittance < 0.5) depth50 = t;
    }
    t += dt;
  }
  if (depth50 > 1e5 && transmittance < 0.98) depth50 = t;
  imageStore(out_color, block, vec4(radiance, transmittance));
  // z: the ray's end (the scene, or the segment's: the split's near pass), which the depth-aware upsample compares.
  imageStore(out_depth, block, vec4(depth50, samples, min(t_scene, E.misc.x), steps));
}
