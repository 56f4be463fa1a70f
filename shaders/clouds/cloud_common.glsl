// Shared by the voxel-cloud passes: the parameter block, the NVDF lookups (modeling, signed
// distance), the up-rez density sampler and the lighting terms of the 2023 talk (seed 000
// "Sampling Density" and "Lighting"; slide code in seed 003). Constants name their source.
//
// Defines (compile-time variants; each pipeline is built once per combination):
//   SDF_BC1             1: the field is the conservative BC1 form, unpacked with dot(rgb, (1, 9/255, 45/65025))
//                       (seed 003 "Decompress BC1": float3(1.0, 0.03529415, 0.00069204)); 0: R16 unorm
//   NOISE_MIP_DISTANCE  1: noise mip from the distance to the camera (talk: about 15 % faster); 0: mip 0
//   COVERAGE_TEXTURE    1: the modeling NVDF is BC1 (three channels): the coverage thresholds come from each asset's
//                       half-resolution coverage texture (one more fetch); 0: the RGBA8 modeling texel's alpha
//                       (the same fetch). Functions that sample an asset take CLOUD_MODELING_PARAMS (its
//                       modeling and, with COVERAGE_TEXTURE, coverage samplers) and are called with
//                       CLOUD_MODELING(modeling, coverage), CLOUD_ASSET_0 or CLOUD_ASSET_1.
#ifndef CUMULO_CLOUD_COMMON_GLSL
#define CUMULO_CLOUD_COMMON_GLSL
#include "shared/cloud_params.h"
#include "clouds/cloud_math.glsl"

#ifndef SDF_BC1
#define SDF_BC1 0
#endif
#ifndef NOISE_MIP_DISTANCE
#define NOISE_MIP_DISTANCE 1
#endif

layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_MODELING) uniform sampler3D modeling_tex;
layout(set = 0, binding = CLOUD_BINDING_FIELD) uniform sampler3D field_tex;
layout(set = 0, binding = CLOUD_BINDING_NOISE) uniform sampler3D noise_tex;
// A second cloudscape asset (CLOUD_ASSET_SLOTS 2: instances whose wind_offset.w is 1 read these). The
// functions below take the asset's samplers as arguments, so one march body serves both slots.
#ifndef CLOUD_ASSET_SLOTS
#define CLOUD_ASSET_SLOTS 1
#endif
#if CLOUD_ASSET_SLOTS > 1
layout(set = 0, binding = CLOUD_BINDING_MODELING_1) uniform sampler3D modeling_tex_1;
layout(set = 0, binding = CLOUD_BINDING_FIELD_1) uniform sampler3D field_tex_1;
#endif
#if CLOUD_ASSET_SLOTS > 2  // a third (wind_offset.w 2)
layout(set = 0, binding = CLOUD_BINDING_MODELING_2) uniform sampler3D modeling_tex_2;
layout(set = 0, binding = CLOUD_BINDING_FIELD_2) uniform sampler3D field_tex_2;
#endif
#ifndef COVERAGE_TEXTURE
#define COVERAGE_TEXTURE 0
#endif
#if COVERAGE_TEXTURE
layout(set = 0, binding = CLOUD_BINDING_COVERAGE) uniform sampler3D coverage_tex;
#if CLOUD_ASSET_SLOTS > 1
layout(set = 0, binding = CLOUD_BINDING_COVERAGE_1) uniform sampler3D coverage_tex_1;
#endif
#if CLOUD_ASSET_SLOTS > 2
layout(set = 0, binding = CLOUD_BINDING_COVERAGE_2) uniform sampler3D coverage_tex_2;
#endif
#define CLOUD_MODELING_PARAMS sampler3D modeling, sampler3D coverage
#define CLOUD_MODELING(m, c) m, c
#else
#define CLOUD_MODELING_PARAMS sampler3D modeling
#define CLOUD_MODELING(m, c) m
#endif
#define CLOUD_ASSET_0 CLOUD_MODELING(modeling_tex, coverage_tex)
#define CLOUD_ASSET_1 CLOUD_MODELING(modeling_tex_1, coverage_tex_1)
#define CLOUD_ASSET_2 CLOUD_MODELING(modeling_tex_2, coverage_tex_2)

// lavapipe (LAVAPIPE.md) runs both sides of an `if` for its 8-lane group even when no lane takes it,
// but stops a loop once every lane is done. So an expensive block that is often empty for the whole
// group (density and light outside clouds) is written as a loop that runs once where `cond` holds:
// the same result, and on a CPU device the block costs nothing when no lane needs it. No `break` or
// `continue` inside (they would bind to this loop).
// Measured on the sample level's ground and immersed views (320x180, 30 Hz, full, frame-interleaved runs):
// the run-once loop nested in the march loop costs about 1.4-1.7x more than a plain `if` (LLVM 15
// lavapipe), so the plain `if` is the default; CLOUD_WHERE_AS_LOOP=1 brings the loop form back to measure.
#ifndef CLOUD_WHERE_AS_LOOP
#define CLOUD_WHERE_AS_LOOP 0
#endif
#if CLOUD_WHERE_AS_LOOP
#define CLOUD_WHERE(cond) for (int cloud_where_once_ = ((cond) ? 1 : 0); cloud_where_once_ > 0; --cloud_where_once_)
#else
#define CLOUD_WHERE(cond) if (cond)
#endif

// Field NVDF decode range (2023 talk: "originally ranged from -256 to 4096 but we scale it to a zero to 1 range").
const float kSdfMin = -256.0;
const float kSdfRange = 4352.0;
// The voxel noise tiles every 100 m (talk: "inSamplePosition * 0.01").
const float kNoiseScale = 0.01;

// The talk's GetFractionFromValue.
float fraction_from_value(float v, float a, float b) { return saturate((v - a) / (b - a)); }

// Ray/box slab test: (t_enter, t_exit) along o + d t; t_enter > t_exit means a miss.
vec2 ray_box(vec3 o, vec3 d, vec3 bmin, vec3 bmax) {
  vec3 inv = 1.0 / d;  // +-inf for axis-parallel rays: IEEE gives the right slabs
  vec3 t0 = (bmin - o) * inv, t1 = (bmax - o) * inv;
  vec3 lo = min(t0, t1), hi = max(t0, t1);
  return vec2(max(max(lo.x, lo.y), lo.z), min(min(hi.x, hi.y), hi.z));
}

vec3 asset_uvw(CloudInstanceParams inst, vec3 asset_pos) {
  return (asset_pos - inst.bounds_min.xyz) / (inst.bounds_max.xyz - inst.bounds_min.xyz);
}

// Signed distance in asset metres (negative inside). Both forms are conservative (never above the
// true distance at texels; bake/bc1.h states the guarantee and its limits between texels).
float cloud_distance(sampler3D field, vec3 uvw) {
#if SDF_BC1
  float v = dot(textureLod(field, uvw, 0.0).rgb, vec3(1.0, 9.0 / 255.0, 45.0 / 65025.0));
#else
  float v = textureLod(field, uvw, 0.0).r;
#endif
  return kSdfMin + kSdfRange * v;
}

// Modeling NVDF: r dimensional profile, g detail type (0 wispy .. 1 billowy), b density scale, a coverage threshold.
struct ModelingData {
  float profile;
  float type;
  float density_scale;
  float presence;  // the weather coverage's presence of this voxel's cloud (0: removed by coverage)
};

// The presence 0..1 of cloud whose coverage threshold is `threshold` at the weather's `coverage`
// (CLOUD_COVERAGE_RAMP, cloud_params.h; the CPU's is density_query.h coverage_presence).
float coverage_presence(float coverage, float threshold) { return saturate(1.0 + (coverage - threshold) / CLOUD_COVERAGE_RAMP); }

// Dissipation (issue 8; the Stormbird's death drives it later): removes low-profile, wispy regions
// first. The profile is re-ranged above a threshold that wispy cloud (type 0) reaches at dissipation
// 2/3 and billowy cloud (type 1) at 1, so at 1 every cloud is gone.
// Coverage (issue 20) removes cloud the same way: a presence p re-ranges the profile above 1 - p (gone at
// p = 0). The two re-rangings compose into one: above t = 1 - (1 - t_dissipation) * p, written so that t is
// exactly t_dissipation where p = 1 (every cloud of a default recipe: threshold 0).
ModelingData modeling_data(CLOUD_MODELING_PARAMS, vec3 uvw, float dissipation, float weather_coverage) {
  vec4 m = textureLod(modeling, uvw, 0.0);
#if COVERAGE_TEXTURE
  m.a = textureLod(coverage, uvw, 0.0).r;
#endif
  ModelingData d;
  float dissipated = saturate(dissipation * mix(1.5, 1.0, m.g));
  d.presence = coverage_presence(weather_coverage, m.a);
  float threshold = dissipated + (1.0 - dissipated) * (1.0 - d.presence);
  d.profile = threshold > 0.0 ? saturate((m.r - threshold) / max(1.0 - threshold, kEpsilon)) : m.r;
  d.type = m.g;
  d.density_scale = m.b;
  return d;
}

// ValueErosion: "We erode the Dimensional profile using a remap function and our noise composite as
// we would for 2.5D clouds" (2017: remap(base, erosion, 1, 0, 1)), the same rule as
// modules/clouds/noise/noise_encode.cpp value_erosion().
float value_erosion(float profile, float erosion) {
  return erosion >= 1.0 ? 0.0 : saturate((profile - erosion) / (1.0 - erosion));
}

// Noise mip from the distance (talk: mipmap_level = log2(1.0 + abs(distance * cVoxelFineDetailMipMapDistanceScale));
// the scale is P.steps.w, the talk does not state its value).
float noise_mip(float dist) {
#if NOISE_MIP_DISTANCE
  return log2(1.0 + abs(dist * P.steps.w));
#else
  return 0.0;
#endif
}

// The up-rez density sampler (talk "Voxel Cloud Density Sampler Up-Rez Function"). Transcription
// slips of the HLSL listing resolved deliberately, each against the slide code that precedes it:
//  - billowy gradient exponent: the slide says pow(profile, 0.25), the listing 0.35; we take 0.25
//    (also what noise_encode.cpp's uprez_density uses, so CPU and GPU agree);
//  - billowy high frequency: the listing reads noise.r, the slide noise.a (A is the high-frequency
//    Alligator channel); we take noise.a;
//  - the listing multiplies by pow(saturate(density_scale), 4) and uses max(1.0, ...) in the sharpen
//    lerp; the slide multiplies by density_scale and uses max(EPSILON, pow(saturate(density_scale), 4));
//    max(1.0, ...) would pin the exponent at 0.6, so we take the slide's form;
//  - the high-frequency blend: the listing's garbled "lerp(1.0 - pow(...), pow(hf_noise.s ...))" is the
//    slide's twice-folded hhf_wisps / hhf_billows blended by detail type; its distance range
//    "58.0, 198.0" is read as 50..150 m after its own comment ("only do the work within a distance of
//    150 meters");
//  - "lower density close to camera" for wispy types (type < 0.5): pow(d, lerp(0.5, 1, f)) *
//    lerp(0.666, 1, f), f = fraction over the same 50..150 m.
// `details`: the near-camera twice-folded noise (off in the light grid and light samples).
// `noise`: the voxel noise at the sample (uprez_density fetches it; the light-grid sweep passes its mean).
float uprez_density_from(ModelingData m, vec4 noise, float dist, bool details) {
  float wispy_noise = mix(noise.r, noise.g, m.profile);
  float billowy_type_gradient = pow(m.profile, 0.25);
  float billowy_noise = mix(noise.b * 0.3, noise.a * 0.3, billowy_type_gradient);
  float noise_composite = mix(wispy_noise, billowy_noise, m.type);
  if (details) {
    float hhf_wisps = 1.0 - pow(abs(abs(noise.g * 2.0 - 1.0) * 2.0 - 1.0), 4.0);
    float hhf_billows = pow(abs(abs(noise.a * 2.0 - 1.0) * 2.0 - 1.0), 2.0);
    float hf_noise = saturate(mix(hhf_wisps, hhf_billows, m.type));
    float hf_blend = value_remap(dist, 50.0, 150.0, 0.9, 1.0);
    noise_composite = mix(hf_noise, noise_composite, hf_blend);
  }
  float d = value_erosion(m.profile, noise_composite) * m.density_scale;
  d = d > 0.0 ? pow(d, mix(0.3, 0.6, max(kEpsilon, pow(saturate(m.density_scale), 4.0)))) : 0.0;
  if (details && m.type < 0.5) {
    float f = fraction_from_value(dist, 50.0, 150.0);
    d = pow(d, mix(0.5, 1.0, f)) * mix(0.666, 1.0, f);
  }
  return d;
}
float uprez_density(ModelingData m, vec3 asset_pos, vec3 wind_offset, float dist, float mip, bool details) {
  return uprez_density_from(m, textureLod(noise_tex, (asset_pos - wind_offset) * kNoiseScale, mip), dist, details);
}

// Density at an asset-space point (0 where the profile is 0: "we are not sampling a cloud and we can
// prevent any further work for this sample"), times the instance's density multiplier.
struct DensitySample {
  float full;     // up-rezzed density: extinction and lighting
  float profile;  // profile * density scale: the scattering-probability fields
  float raw_profile;
  float presence;  // ModelingData.presence: 0 where the weather's coverage removed the cloud
};
DensitySample sample_density(CLOUD_MODELING_PARAMS, CloudInstanceParams inst, vec3 asset_pos, float dist, float mip, bool details) {
  ModelingData m = modeling_data(CLOUD_MODELING(modeling, coverage), asset_uvw(inst, asset_pos), inst.sky_dir.w, inst.weather.x);
  DensitySample s;
  s.raw_profile = m.profile;
  s.presence = m.presence;
  s.profile = m.profile * m.density_scale * inst.sun_dir.w;
  s.full = 0.0;
  CLOUD_WHERE(m.profile > 0.0) s.full = uprez_density(m, asset_pos, inst.wind_offset.xyz, dist, mip, details) * inst.sun_dir.w;
  return s;
}

// The same with a given noise value (no noise fetch): where the caller's resolution is far coarser than
// the noise, which then contributes only its mean (the light-grid sweep).
DensitySample sample_density_with_noise(CLOUD_MODELING_PARAMS, CloudInstanceParams inst, vec3 asset_pos, vec4 noise) {
  ModelingData m = modeling_data(CLOUD_MODELING(modeling, coverage), asset_uvw(inst, asset_pos), inst.sky_dir.w, inst.weather.x);
  DensitySample s;
  s.raw_profile = m.profile;
  s.presence = m.presence;
  s.profile = m.profile * m.density_scale * inst.sun_dir.w;
  s.full = m.profile > 0.0 ? uprez_density_from(m, noise, 1e4, false) * inst.sun_dir.w : 0.0;
  return s;
}

// The voxel noise's mean: its last mip's single texel.
vec4 noise_mean() { return textureLod(noise_tex, vec3(0.5), float(textureQueryLevels(noise_tex) - 1)); }

// Dual-lobe HG (2017 talk's silver lining: a forward lobe toward the sun plus a backward lobe); `eccentricity` scales
// both lobes' g (an order of scattering past the first keeps a share of it: march_render.comp's forward lobe).
float dual_lobe_phase(float cos_theta, float eccentricity) {
  return mix(henyey_greenstein(cos_theta, eccentricity * P.phase.y), henyey_greenstein(cos_theta, eccentricity * P.phase.x), P.phase.z);
}
float dual_lobe_phase(float cos_theta) { return dual_lobe_phase(cos_theta, 1.0); }


#endif
