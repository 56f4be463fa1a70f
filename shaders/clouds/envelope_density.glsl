// The Envelope method's density (issue 24; seed 000 "Envelope Method", "Envelope Method Dimensional Profile
// Construction"), shared by the march (envelope_march.comp) and the probe (envelope_probe.comp); the CPU mirror of
// the profile is modules/clouds/envelope/envelope_bake.h envelope_profile.
//
//   height_fraction = remap(height, min_height, max_height, 0, 1)
//   top_gradient = pow(1 - height_fraction, 1.5), bottom_gradient = pow(height_fraction, 2)
//   edge_gradient = saturate(distance inside the footprint's side / edge width)
//   profile = bottom_gradient * top_gradient * edge_gradient / kProfilePeak * coverage
// Two gaps of the talk closed here: its product of the top and bottom gradients peaks at (3/7)^1.5 (4/7)^2 = 0.0916
// (at a height fraction of 4/7), so it is divided by that peak before the shared up-rez (which erodes 1 - profile
// from noise in 0..1: unnormalised, nothing would survive); and its edge gradient, remap(sample_height, 0, 35, 1, 0),
// "increases in value going in from the sides": we read sample_height as the distance still to go to a band 35 m
// inside the side, i.e. the gradient rises from 0 at the side to 1 at 35 m in.
// Up-rez (the talk: "noise_composite = lerp(wispy_noise, billowy_noise, detail_type)", "cloud_density =
// saturate(noise - (1.0 - dimensional_profile))", the noise scrolled by the wind for pseudomotion) on the Nubis noise
// of that generation (the 2.5D sky's: Perlin-Worley for the wispy composite, Worley fBm for the billowy one), then
// an optional erosion by the high-frequency Worley noise (E.noise.z; 0 = the talk's form) for near-camera detail.
#ifndef CUMULO_ENVELOPE_DENSITY_GLSL
#define CUMULO_ENVELOPE_DENSITY_GLSL
#include "shared/envelope_params.h"
#include "clouds/cloud_math.glsl"
#include "engine/runtime_uniform.glsl"

// ENV_BINDING_OFFSET: added to the bindings below (the path tracer binds the envelope beside the voxel clouds).
#ifndef ENV_BINDING_OFFSET
#define ENV_BINDING_OFFSET 0
#endif
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_PARAMS, std140) uniform EnvelopeBlock { EnvelopeParams E; };
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_SHAPE) uniform sampler2D shape_tex;
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_STEPS) uniform sampler2D steps_tex;
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_AUX) uniform sampler2D aux_tex;
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_BASE_NOISE) uniform sampler3D base_noise;
layout(set = 0, binding = ENV_BINDING_OFFSET + ENV_BINDING_DETAIL_NOISE) uniform sampler3D detail_noise;

const float kProfilePeak = 0.0916133417;  // (3/7)^1.5 (4/7)^2

vec2 env_uv(vec2 xz) { return (xz - E.map.xy) / (E.map.z * E.map.w); }
ivec2 env_texel(vec2 xz) { return clamp(ivec2(floor((xz - E.map.xy) / E.map.z)), ivec2(0), ivec2(int(E.map.w) - 1)); }

float envelope_profile(float y, vec4 shape, float edge_m) {
  if (shape.z <= 0.0 || shape.y <= shape.x) return 0.0;
  float hf = (y - shape.x) / (shape.y - shape.x);
  if (hf <= 0.0 || hf >= 1.0) return 0.0;
  float top_gradient = pow(1.0 - hf, 1.5);
  float bottom_gradient = hf * hf;
  float edge_gradient = saturate(edge_m / max(E.heights.z, 1e-3));
  return bottom_gradient * top_gradient * edge_gradient / kProfilePeak * saturate(shape.z * E.noise.w);
}

// 0 inside a voxel cloudscape's box, 1 beyond E.misc.w metres of it: where the two methods meet, the voxel clouds own
// the space and the envelope fades out before it (no cloud counted twice; the sample level's envelope clouds stay
// below its cloudscape's 600 m base). Only lowers the density, so the cone steps stay safe.
float envelope_yield(vec3 p) {
  float m = 1.0;
  for (int i = 0; i < runtime_int(E.misc.z); ++i) {
    vec3 outside = max(max(E.yield_min[i].xyz - p, p - E.yield_max[i].xyz), vec3(0.0));
    m *= smoothstep(0.0, max(E.misc.w, 1e-3), length(outside));
  }
  return m;
}

struct EnvelopeSample {
  float density;  // up-rezzed, times the density multiplier (extinction: x E.wind.w)
  float profile;
  float hf;       // height fraction in the envelope
  float edge;     // the edge gradient
};

// The detail noise's erosion of a density (0..1, before the multiplier) by its fBm there (the view ray) or by the fBm's
// mean (the slab lighting's light samples, envelope_march.comp; a mean of 0 leaves the density as it is).
float envelope_erode(float d, float fbm) {
  float k = fbm * E.noise.z * 0.25;
  return saturate((d - k) / max(1.0 - k, 1e-3));
}

// `detail`: the high-frequency erosion (off in the light samples).
EnvelopeSample envelope_sample(vec3 p, bool detail) {
  EnvelopeSample s;
  s.density = 0.0;
  vec2 uv = env_uv(p.xz);
  vec4 shape = textureLod(shape_tex, uv, 0.0);
  float edge_m = textureLod(aux_tex, uv, 0.0).y;
  s.hf = saturate((p.y - shape.x) / max(shape.y - shape.x, 1e-3));
  s.edge = saturate(edge_m / max(E.heights.z, 1e-3));
  s.profile = envelope_profile(p.y, shape, edge_m);
  if (s.profile <= 0.0) return s;
  s.profile *= envelope_yield(p);
  if (s.profile <= 0.0) return s;
  vec3 q = p - E.wind.xyz;
  vec4 b = textureLod(base_noise, q / E.noise.x, 0.0);
  float worley_fbm = b.g * 0.625 + b.b * 0.25 + b.a * 0.125;
  float wispy_noise = saturate((b.r - (worley_fbm - 1.0)) / (2.0 - worley_fbm));  // Perlin-Worley shaped by Worley (2015)
  float billowy_noise = worley_fbm;
  float noise_composite = mix(wispy_noise, billowy_noise, shape.w);
  float d = saturate(noise_composite - (1.0 - s.profile));
  if (detail && d > 0.0 && E.noise.z > 0.0) {
    vec3 dn = textureLod(detail_noise, q / E.noise.y, 0.0).rgb;
    d = envelope_erode(d, dn.r * 0.625 + dn.g * 0.25 + dn.b * 0.125);
  }
  s.density = d * E.heights.w;
  return s;
}

#endif
