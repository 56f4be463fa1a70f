#version 450
// The voxel cloud ray-march (2023 talk, seed 000 "Ray-Marching", "Sampling Density", "Lighting",
// "30hz, 60hz, 40hz"; slide code in seed 003).
//
// Per pixel, per instance (in order of entry distance): the view ray is clipped to the instance's
// transformed box and to the scene depth ("ends where it intersects the voxel grid bounding box or
// where it intersects geometry, whichever is closer"), then marched:
//   adaptive_step = max(1.0, max(sqrt(distance), EPSILON) * 0.08)        (talk)
//   step          = max(sdf_cloud_distance, adaptive_step)                (talk)
//   (CloudSettings::step_growth > 1: the in-cloud step grows behind an optical depth and in thin cloud, below)
//   sample at distance + jitter, jitter = hash * step * P.misc.x, hash animated per frame within
//   P.steps.y (the talk: 250 m, "distance_from_camera < 250.0 ? animated_hash : static_hash"; by default every
//   distance, --cloud-jitter), static beyond.
//   The talk's two listings disagree on where the jitter goes (the slide adds it to the step, the HLSL
//   offsets only the sample position); we offset the sample position inside its step, which keeps the
//   step placement of the SDF exact and spreads samples uniformly over the step.
//   Density and light only where the SDF is negative; stop when transmittance < P.march.z.
// Light per sample: direct = sun * (Beer-Lambert(optical depth) * dual-lobe HG + multiple-scattering
// probability * ms strength / 4 pi), the optical depth from 2 marched samples (P.light.x m each; the count and
// their growth are settings, P.light_march) and
// then the light grid ("The first two samples are taken as we did before but the remaining samples
// are pre-computed ... stored in a 256x256x32 voxel grid that we sample after the first two samples");
//   ms_volume = profile * exp(-od_sun * Remap(sun_dot, 0.0, 0.9, 0.25, ValueRemap(cloud_distance, -128, 0, 0.05, 0.25)))
//   (the talk's 0.05 and 0.25 are P.ms.x and P.ms.y, CloudSettings::ms_attenuation_inside / ms_attenuation)
// (talk; the summed density is taken as optical depth, i.e. times the extinction coefficient);
//   ambient = pow(1 - profile, 0.5) * exp(-od_sky) * ambient colour                  (talk)
// (od_sky = summed sky density x extinction x P.light.y: the talk does not give the scale of its
// "summed_ambient_density"; at full extinction the base of a 400 m cumulus would be black, while the
// bounce and multiple scattering the ambient term stands for keep it grey);
//   point lights: pow(1 - d / radius, 12) * (1 - saturate(density * 5)) * colour      (talk, lightning)
// The slab lighting (issue 21; CloudSettings::ms_slab, `--cloud-lighting slab`) replaces the falloff of the
// multiple scattering by a slab's along the sun's line, reads the sky from the upper hemisphere through the phase
// function, adds the sky's light diffused into the cloud and a ground bounce (comments at each term below).
// Integration: energy-conserving (Hillaire 2016, "Physically Based Sky, Atmosphere and Cloud
// Rendering in Frostbite"): Sint = (S - S * exp(-sigma_t dt)) / sigma_t.
// Output: rgb in-scattered radiance, a transmittance; depth image x = distance where opacity reached
// 0.5 (else the first cloud sample, else 1e6), y = steps taken, z = end of the clipped segment.
//
// Defines: ABLATION (cloud_params.h CLOUD_ABLATION_*), SEGMENT (CLOUD_SEGMENT_*), SDF_BC1, COVERAGE_TEXTURE, NOISE_MIP_DISTANCE,
//   LIGHT_SAMPLE_NOISE_MEAN (1: the two marched light samples take the noise's mean instead of sampling it;
//   a 24 m sample integrates over far more than a noise texel, and it saves two trilinear mip fetches per
//   sample, ~20 % of the march on lavapipe; 0: the talk's "taken as we did before").
//   The far segment (40/60 Hz) reads the near layer's transmittance and stops where it is opaque: without
//   that, the far march would redo, unseen, the dense cloud work the near layer already hid.
//   base:           uniform step P.steps.z (world m) over the clipped segment, density at every step,
//                   sun optical depth from a P.light.w-sample, P.light.z-metre light march ("Here is what it
//                   would look like with a 256 meter, 10 sample light ray march as we did before");
//   voxel-lighting: base stepping + 2 marched light samples + the light grid;
//   full:           + the SDF and adaptive step placement.
// All three read the sky channel of the light grid for ambient (the same lighting; only the sun's
// march and the step placement differ), so they draw the same picture within a tolerance.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

#ifndef ABLATION
#define ABLATION CLOUD_ABLATION_FULL
#endif
#ifndef SEGMENT
#define SEGMENT CLOUD_SEGMENT_ALL
#endif
#ifndef LIGHT_SAMPLE_NOISE_MEAN
#define LIGHT_SAMPLE_NOISE_MEAN 1
#endif
#ifndef MS_FIELD
#define MS_FIELD 0
#endif

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_LIGHT_GRID) uniform sampler3D light_grid_tex;
layout(set = 0, binding = CLOUD_BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = CLOUD_BINDING_OUT_COLOR, rgba16f) uniform writeonly image2D out_color;
layout(set = 0, binding = CLOUD_BINDING_OUT_DEPTH, rgba32f) uniform writeonly image2D out_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };
layout(set = 0, binding = CLOUD_BINDING_FIELD_FAIR) uniform sampler3D field_fair_tex;
#if CLOUD_ASSET_SLOTS > 1
layout(set = 0, binding = CLOUD_BINDING_FIELD_FAIR_1) uniform sampler3D field_fair_tex_1;
#endif
#if CLOUD_ASSET_SLOTS > 2
layout(set = 0, binding = CLOUD_BINDING_FIELD_FAIR_2) uniform sampler3D field_fair_tex_2;
#endif

// The distance the march steps through air by: in fair weather (inst.weather.y, CLOUD_COVERAGE_BAND) the
// fair-weather field's, which ignores the clouds the weather has removed; where that reads inside (or without
// one: its stand-in reads -256 m) the field's, so sampling and the in-cloud step are as before.
float march_distance(sampler3D field, sampler3D fair, CloudInstanceParams inst, vec3 uvw) {
  float d = inst.weather.y > 0.5 ? kSdfMin + kSdfRange * textureLod(fair, uvw, 0.0).r : -1.0;
  // The field's fetch only where the fair field says inside (or there is none): as a loop, which lavapipe skips when
  // no lane of the group needs it (a select fetched both: issue 23, 5-15 % of the march in the sample's views).
  for (int once = d >= 0.0 ? 0 : 1; once > 0; --once) d = cloud_distance(field, uvw);
  return d;
}
// World metres from a world point to instance i's nearest cloud (its signed distance, conservative; inside its box).
float instance_distance(int i, vec3 world_pos) {
  CloudInstanceParams inst = P.instances[i];
  vec3 uvw = asset_uvw(inst, (inst.world_to_asset * vec4(world_pos, 1.0)).xyz);
#if CLOUD_ASSET_SLOTS > 2
  if (inst.wind_offset.w > 1.5) return march_distance(field_tex_2, field_fair_tex_2, inst, uvw) * inst.bounds_min.w;
#endif
#if CLOUD_ASSET_SLOTS > 1
  if (inst.wind_offset.w > 0.5) return march_distance(field_tex_1, field_fair_tex_1, inst, uvw) * inst.bounds_min.w;
#endif
  return march_distance(field_tex, field_fair_tex, inst, uvw) * inst.bounds_min.w;
}
#if SEGMENT == CLOUD_SEGMENT_FAR
layout(set = 0, binding = CLOUD_BINDING_NEAR_IN) uniform sampler2D near_color;
#endif

// The optical depth a grown in-cloud step may span at the last sample's extinction (CloudSettings::step_growth).
const float kStepOpticalDepth = 0.1;

struct PixelData {
  vec3 radiance;
  float transmittance;
  float depth50;
  float first_hit;
  float steps;
  float profile_opacity;  // debug view: the profile composited as if it were density
};

#include "clouds/light_grid_lookup.glsl"
#include "engine/view_ray.glsl"
#include "engine/runtime_uniform.glsl"

// What the march reads of the light grids at the sample (light_grid_local.comp): x, y the other instances' summed
// density toward the sun and the sky, z the own sky sum, w the own sum away from the sun; 0 outside the box.
layout(set = 0, binding = CLOUD_BINDING_LIGHT_LOCAL) uniform sampler3D light_local_tex;
vec4 light_local(int i, vec3 asset_pos) { return instance_slab_fetch(light_local_tex, i, asset_pos); }

// MS_FIELD 1 (CloudSettings::ms_solve): the sun's multiple scattering solved by diffusion on the light grid
// (light_grid_diffusion.comp): the scattered light's fluence per unit sun irradiance at an asset-space point,
// trilinear between voxels (outside the box: none), stacked per instance as the light grid is.
#if MS_FIELD
layout(set = 0, binding = CLOUD_BINDING_MS_FIELD) uniform sampler3D ms_field_tex;
float solved_fluence(int i, vec3 asset_pos) { return instance_slab_fetch(ms_field_tex, i, asset_pos).w; }
#endif

// The terrain between a cloud sample and the key light (issue 10: "the sun behind a mountain darkens
// the cloud base near it"): the geometry's depth map from the light (render/light_depth.h), with the
// shadow's edge softened over 40 m of depth.
#ifndef TERRAIN_SHADOW
#define TERRAIN_SHADOW 0
#endif
#if TERRAIN_SHADOW
layout(set = 0, binding = CLOUD_BINDING_TERRAIN_DEPTH) uniform sampler2D terrain_depth_tex;
float terrain_visibility(vec3 world) {
  vec4 c = P.light_depth * vec4(world, 1.0);
  vec3 n = c.xyz / c.w;
  vec2 uv = n.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || n.z <= 0.0) return 1.0;
  float occluder = textureLod(terrain_depth_tex, uv, 0.0).r;
  return saturate(1.0 - (n.z - occluder) * P.haze.w / 40.0);
}
#else
float terrain_visibility(vec3 world) { return 1.0; }
#endif

// Optical depth toward the sun from an asset-space point (world metres of density x extinction): x the whole
// path's, y its part inside the point's own cloud (up to the first sample outside every cloud's profile; the
// light grid's z channel beyond the two marched samples), which the diffusion lighting tells apart (issue 21).
// The own cloud goes on across air under a sky optical depth of P.sun_dir.w or more (enclosed air: a chamber inside
// a cloud does not part it in two; 0: the own cloud ends at the first air). `sky`: the light grid's y there.
bool still_own(DensitySample s, float sky) {
  return s.raw_profile > 0.0 || (P.sun_dir.w > 0.0 && sky * P.march.x >= P.sun_dir.w);
}
vec2 sun_optical_depth(CLOUD_MODELING_PARAMS, int i, CloudInstanceParams inst, vec3 p, float dist, float mip, vec4 mean_noise) {
  vec3 sun = inst.sun_dir.xyz;
  float scale = inst.bounds_min.w, inv_scale = inst.bounds_max.w;
  float sum = 0.0, own = 0.0;
  bool in_own = true;
#if ABLATION == CLOUD_ABLATION_BASE
  float seg = P.light.z / P.light.w;  // world metres per light sample
  uint n = uint(P.light.w);
  for (uint k = 0u; k < n; ++k) {
    vec3 q = p + sun * ((float(k) + 0.5) * seg * inv_scale);
    DensitySample s = sample_density(CLOUD_MODELING(modeling, coverage), inst, q, dist, mip, false);
    in_own = in_own && still_own(s, 0.0);
    sum += s.full * seg;
    own += in_own ? s.full * seg : 0.0;
  }
#else
  // The marched samples before the grid: P.light_march.x of them, the first P.light.x world metres long and each
  // next one P.light_march.y times longer, P.light_march.z metres in all (the talk: two of 24 m).
  float seg = P.light.x;
  // The grid beyond the marched samples (its sky sum also says whether air on their way is enclosed).
  bool grid_on = (P.effects.x & CLOUD_EFFECT_LONG_SHADOWS) != 0u;
  vec4 g = grid_on ? light_grid(i, p + sun * (P.light_march.z * inv_scale)) : vec4(0.0);
  float along = 0.0;
  uint n_marched = uint(P.light_march.x);
  for (uint k = 0u; k < n_marched; ++k) {
    vec3 q = p + sun * ((along + 0.5 * seg) * inv_scale);
#if LIGHT_SAMPLE_NOISE_MEAN
    DensitySample s = sample_density_with_noise(CLOUD_MODELING(modeling, coverage), inst, q, mean_noise);
#else
    DensitySample s = sample_density(CLOUD_MODELING(modeling, coverage), inst, q, dist, mip, false);
#endif
    in_own = in_own && still_own(s, g.y);
    sum += s.full * seg;
    own += in_own ? s.full * seg : 0.0;
    along += seg;
    seg *= P.light_march.y;
  }
  if (grid_on) {
    sum += g.x;
    own += in_own ? g.z : 0.0;
  }
#endif
  return vec2(sum, own) * P.march.x;
}

// The forward lobe past the first order's share of the phase's eccentricity (march_instance's forward_phase;
// cloud_renderer.cpp kSlabMsForward says how it was measured).
const float kForwardEccentricity = 0.7;

// `t_front`: transmittance in front of this segment (the near layer's, for the far march; 1 otherwise).
// It only ends the march early (where the near layer is already opaque the far one cannot show); the
// far layer's own radiance and transmittance stay unattenuated for the merge.
void march_instance(CLOUD_MODELING_PARAMS, sampler3D field, sampler3D fair, int i, vec3 ro, vec3 rd, float t_begin, float t_end, float hash_animated, float hash_static,
                    float t_front, vec4 mean_noise, inout PixelData px) {
  CloudInstanceParams inst = P.instances[i];
  vec3 ao = (inst.world_to_asset * vec4(ro, 1.0)).xyz;
  vec3 ad = mat3(inst.world_to_asset) * rd;  // |ad| = 1 / scale: asset point at world distance t is ao + ad t
  vec2 seg = ray_box(ao, ad, inst.bounds_min.xyz, inst.bounds_max.xyz);
  float t = max(seg.x, t_begin);
  float t1 = min(seg.y, t_end);
  float scale = inst.bounds_min.w;
  float sun_dot = dot(rd, P.sun_dir.xyz);
  bool silver_lining = (P.effects.x & CLOUD_EFFECT_SILVER_LINING) != 0u;
  float phase = silver_lining ? dual_lobe_phase(sun_dot) : henyey_greenstein(sun_dot, P.phase.y);
  // The forward lobe past the first order (slab, P.slab.w = strength; with the silver lining, whose lobe it is): light
  // scattered within the phase's forward lobe goes on near the sun's direction, so it reaches deeper than the direct
  // light (Wrenninge's first octave: a quarter of the optical depth, kForwardEccentricity of the lobes'
  // eccentricity). Only its excess over the isotropic: the slab's diffused light already counts the rest. One per ray.
  float forward_phase = 0.0;
  if (silver_lining)
    forward_phase = P.slab.w * max(dual_lobe_phase(sun_dot, kForwardEccentricity) - 1.0 / (4.0 * kPi), 0.0);
  float ms_strength = (P.effects.x & CLOUD_EFFECT_INNER_GLOW) != 0u ? P.phase.w : 0.0;
  bool dark_edges = (P.effects.x & CLOUD_EFFECT_DARK_EDGES) != 0u;
  bool ambient_direction = (P.effects.x & CLOUD_EFFECT_AMBIENT_DIRECTION) != 0u;
  uint point_lights = (P.effects.x & CLOUD_EFFECT_LIGHTNING_GLOW) != 0u ? P.frame.z : 0u;
  float ext = P.march.x, albedo = P.march.y;
  uint max_steps = uint(P.march.w);
#if ABLATION == CLOUD_ABLATION_FULL
  // Inside a cloud that the weather's coverage has removed (presence 0) there is nothing to sample, but the
  // SDF (baked for every cloud, whatever its threshold) gives no distance to skip: step two field voxels
  // (world metres) there instead of the in-cloud step. Thresholds are filtered, so a present cloud begins at
  // least a voxel beyond the last absent texel; the jitter hides the rest. Issue 20: an overcast deck of
  // absent sheets cost a fair-weather view ~2x its steps without this.
  float absent_step = 2.0 * (inst.bounds_max.x - inst.bounds_min.x) / float(textureSize(field, 0).x) * scale;
#endif
  float sigma_prev = 1e30;  // the last sample's extinction (1/m): none yet
  // The cavity (slab, P.slab.y > 0): where the ray entered this stretch of cloud from a chamber's air (the air at
  // air_t: its optical depths toward the sun, toward the sky and away from the sun all of the enclosed depth or more), the
  // surface it crossed faces walls of cloud on every side, which send back the light it loses: an integrating
  // sphere, so the dark edges' in-scatter deficit is not there (cavity 1).
  float air_t = -1.0, cloud_t = -1.0, cavity = 0.0;
  for (uint s = 0u; s < max_steps; ++s) {
    if (t >= t1 || px.transmittance * t_front < P.march.z) break;
    px.steps += 1.0;
#if ABLATION == CLOUD_ABLATION_FULL
    float sdf = march_distance(field, fair, inst, asset_uvw(inst, ao + ad * t)) * scale;  // world metres
    float adaptive = max(1.0, max(sqrt(t), kEpsilon) * 0.08);
    // Steps in air, where no sample is taken, in a loop of their own: lavapipe runs the sample block
    // below for a group of 8 pixels whenever one of them is in cloud, and a lane in air would pay for
    // it at each of its SDF steps; this loop ends for a lane when it reaches cloud (or the segment's
    // end), so air steps cost one fetch. The same steps and samples as one loop (bit-exact).
    while (sdf >= 0.0 && s + 1u < max_steps) {
      air_t = t;
      t += max(sdf, adaptive);
      if (t >= t1) break;
      ++s;
      px.steps += 1.0;
      sdf = march_distance(field, fair, inst, asset_uvw(inst, ao + ad * t)) * scale;
      adaptive = max(1.0, max(sqrt(t), kEpsilon) * 0.08);
    }
    if (t >= t1) break;
    // The in-cloud step grows (up to P.light_march.w times the talk's; 1: the talk's step) where a sample
    // weighs little or changes little: behind an optical depth, as 1 / sqrt(T) (T counts the near layer in
    // front of a far segment too), and in thin cloud, until a step's optical depth at the last sample's
    // extinction reaches kStepOpticalDepth (0 density inside the SDF's cloud: the air of a chamber).
    float growth = max(inversesqrt(max(px.transmittance * t_front, 1e-6)), kStepOpticalDepth / (sigma_prev * adaptive));
    float step_len = max(sdf, adaptive * clamp(growth, 1.0, P.light_march.w));
    bool inside = sdf < 0.0;
#else
    float step_len = P.steps.z;
    bool inside = true;
    float sdf = -1.0;
#endif
    float hash = t < P.steps.y ? hash_animated : hash_static;
    float ts = t + hash * step_len * P.misc.x;
    float dt = min(step_len, t1 - t);
    CLOUD_WHERE(inside && ts < t1) {
      vec3 q = ao + ad * ts;
      float mip = noise_mip(ts);
      DensitySample ds = sample_density(CLOUD_MODELING(modeling, coverage), inst, q, ts, mip, true);
      if (!(ds.full > 0.0)) sigma_prev = 1e-7, air_t = ts;
      CLOUD_WHERE(ds.full > 0.0) {
        if (air_t > cloud_t && P.slab.y + runtime_zero() > 0.0) {  // (runtime_uniform.glsl: lavapipe would inline it)
          // Past the enclosed depth (P.sun_dir.w > 0 wherever P.slab.y is: cloud_renderer.cpp), fully at twice it.
          vec3 past = smoothstep(vec3(P.sun_dir.w), vec3(2.0 * P.sun_dir.w), light_grid(i, ao + ad * air_t).xyw * ext);
          cavity = P.slab.y * past.x * past.y * past.z;
        }
        cloud_t = ts;
#if ABLATION != CLOUD_ABLATION_FULL
        sdf = cloud_distance(field, asset_uvw(inst, q)) * scale;  // for the ms relaxation only
#endif
        vec2 od = sun_optical_depth(CLOUD_MODELING(modeling, coverage), i, inst, q, ts, mip, mean_noise);
        vec3 world_q = ro + rd * ts;
        bool slab = P.ms.z > 1.5;
        bool long_shadows = (P.effects.x & CLOUD_EFFECT_LONG_SHADOWS) != 0u;
        // One fetch for the sky, the slab and the other instances' clouds in the way (the long shadows' grid term).
        vec4 local = ambient_direction || slab || long_shadows ? light_local(i, q) : vec4(0.0);
        vec2 od_others = long_shadows ? local.xy * ext : vec2(0.0);
        od.x += od_others.x;
        float od_sun = od.x;
        float od_sky = ambient_direction ? (local.z * ext + od_others.y) * P.light.y : 0.0;
        // Diffusion (P.ms.z): the multiple scattering crosses the point's own cloud as diffuse light does,
        // 1 / (1 + 0.75 (1 - g) od); the optical depth of other clouds between it and the sun (od.x - od.y)
        // shadows it by Beer-Lambert at P.ms.w of the extinction: diffused light leaves a cloud in every
        // direction, and little of it crosses the air to another.
        // Slab (P.ms.z = 2): diffusion through the whole own cloud along the sun's line, od.y toward the sun and
        // the light grid's w away from it: a slab's fluence is linear in depth between extrapolated boundaries
        // 2/3 of a transport mean free path outside it, 2 (tau_away' + 2/3) / (tau' + 4/3), which is the
        // diffusion form at the far side (tau_away 0) and twice it at the lit side (light reflected back), so the
        // middle of a thick cloud and the walls of a chamber in it keep half the light, not 1 / (1 + tau / 2).
        // The slab's transport takes the phase function's mean cosine (the dual lobe's, w g_f + (1 - w) g_b = 0.47),
        // the diffusion preset the forward lobe's g (0.8), as calibrated.
        float g_mean = mix(P.phase.y, P.phase.x, P.phase.z);
        float r = 1.0 - (slab ? g_mean : P.phase.x);
        float away = slab ? local.w * ext : 0.0;
        float ms_falloff = P.ms.z > 0.5 ? exp(-P.ms.w * max(od.x - od.y, 0.0)) * (1.0 + 1.5 * r * away) / (1.0 + 0.75 * r * (od.y + away))
                                        : exp(-od_sun * value_remap(sun_dot, 0.0, 0.9, P.ms.y, value_remap(sdf, -128.0, 0.0, P.ms.x, P.ms.y)));
        // The dark edges' in-scatter probability: the talks' profile (0 at a cloud's edge, 1 deep in), or (slab,
        // P.sky_horizon.w > 0) the optical depth to the nearest surface, 1 - exp(-k x depth x sigma): the profile's
        // meaning differs between a recipe's clouds and grown ones, the optical depth does not.
        float tau_surface = max(-sdf, 0.0) * ds.full * ext;  // the optical depth to the nearest surface (local density)
        // The sky through the nearest surface (slab, P.slab.z > 0): the column straight up is one direction of the
        // sky's hemisphere; a point near a cloud's side sees the sky through that side. A face of normal n sees
        // (1 + n.y) / 2 of the upper hemisphere (the SDF's vertical gradient, two fetches), through the optical depth to
        // it; the sky's light takes the more open of the two ways. Past an optical depth of 4 to the surface (under 2 %
        // of the sky) the two fetches are skipped.
        if (slab && ambient_direction && tau_surface < 4.0 && P.slab.z + runtime_zero() > 0.0) {
          vec3 up_a = mat3(inst.world_to_asset)[1];  // asset units per world metre, straight up
          float e = 2.0 * (inst.bounds_max.y - inst.bounds_min.y) / float(textureSize(field, 0).y) * scale;  // two field voxels (m)
          float d_up = cloud_distance(field, asset_uvw(inst, q + up_a * e)) * scale;
          float d_dn = cloud_distance(field, asset_uvw(inst, q - up_a * e)) * scale;
          float ny = clamp((d_up - d_dn) / (2.0 * e), -1.0, 1.0);
          float open_side = min(P.slab.z * 0.5 * (1.0 + ny), 1.0) * exp(-tau_surface);
          od_sky = min(od_sky, -log(max(open_side, 1e-6)));
        }
        float edge = inst.sun_dir.w;
        if (dark_edges) edge = slab && P.sky_horizon.w > 0.0 ? inst.sun_dir.w * (1.0 - (1.0 - cavity) * exp(-P.sky_horizon.w * tau_surface)) : ds.profile;
        // Lateral leak (slab, P.sun_color.w = c > 0): the slab's boundaries lie along the sun's line; where the
        // nearest surface (the SDF's depth x the density) is nearer than both ends of that line, the diffused light
        // leaks out through it on its way in, as in a slab of that half-thickness lit edge-on.
        if (slab && P.sun_color.w > 0.0)
          ms_falloff *= exp(-P.sun_color.w * r * max(min(od.y, away) - tau_surface, 0.0) / (2.0 * r * tau_surface + 4.0 / 3.0));
        // Incidence (slab, P.slab.x > 0): the slab along the sun's line takes the light as entering a face square to
        // it. Where that line leaves the own cloud through its top (its optical depth about the sky column's over the
        // sun's sine: a flat cloud), the light enters a horizontal face, which receives the sine of the sun's elevation
        // of the irradiance; where it leaves through a side (a tower lit from the side), a face square to the sun.
        if (slab && P.slab.x + runtime_zero() > 0.0) {  // (runtime_uniform.glsl: lavapipe would inline it)
          float mu0 = max(P.sun_dir.y, 0.0);
          float through_top = saturate(mu0 * od.y / max(local.z * ext, 1e-3));
          ms_falloff *= mix(1.0, mix(1.0, mu0, through_top), P.slab.x);
        }
#if MS_FIELD
        // The solved field (its leaks through every surface included), weighed against the slab's falloff.
        ms_falloff = mix(ms_falloff, solved_fluence(i, q) * uintBitsToFloat(P.effects.w), uintBitsToFloat(P.effects.z));
#endif
        float ms = edge * ms_falloff;
        // The multiple scattering's phase (slab, P.sky_zenith.w > 0): the first orders of scattering keep the phase's
        // forward lobe, so near the lit surface the field is anisotropic (Wrenninge's octaves narrow their
        // eccentricity by c^n); here an HG of the mean cosine x P.sky_zenith.w, fading with the own cloud's depth
        // toward the sun as diffusion does (more orders, more isotropic). 1 / 4 pi: isotropic (the talks').
        float ms_phase = 1.0 / (4.0 * kPi);
        if (slab && P.sky_zenith.w > 0.0)
          ms_phase = henyey_greenstein(sun_dot, P.sky_zenith.w * g_mean / (1.0 + 0.75 * r * od.y));
        // The forward lobe sees a quarter of the optical depth: the direct light's transmittance is its fourth power (one exp).
        float quarter = exp(-0.25 * od_sun), quarter2 = quarter * quarter;
        vec3 light_in = P.sun_color.rgb * (terrain_visibility(world_q) * (quarter2 * quarter2 * phase + ms * ms_strength * ms_phase +
                                                                           edge * forward_phase * quarter));
        // The sky's light: the talks' isotropic ambient takes it from the whole sphere; the slab takes it from the
        // upper hemisphere only, weighted by the phase function there (sky_share, first order in the phase's mean
        // cosine: a cloud seen from below forward-scatters the sky, one seen from above the ground), and the lower
        // hemisphere's share (1 - sky_share) from the ground (the bounce, below).
        float sky_share = slab ? saturate(0.5 + 0.75 * g_mean * rd.y) : 1.0;
        light_in += P.ambient_color.rgb * (sky_share * pow(1.0 - saturate(ds.raw_profile), 0.5) * exp(-od_sky));
        // The slab's sky light diffused into the cloud as the sun's is (irradiance pi x the sky's radiance, so
        // strength / 4 where the sun's is strength / 4 pi), through the column above the point (its optical depth
        // at the preset's full extinction, P.light.y = 1).
        if (slab)
          light_in += P.ambient_color.rgb * (edge * ms_strength * 0.25 / (1.0 + 0.75 * r * od_sky));
        // Ground bounce (slab, P.ambient_color.w = the ground's albedo): the ground's radiance, lit by the sun and the
        // sky (P.ground_light: the sky's horizontal irradiance, not its mean radiance, which the bright band at the
        // horizon a ground sees at a grazing angle pulls up), seen through the own cloud below the point, for which
        // the depth away from the sun stands (the sun is high where the bounce matters); so a base gets it and a
        // sunlit side or a top does not.
        if (P.ambient_color.w > 0.0)
          light_in += P.ground_light.rgb * (P.ambient_color.w * (1.0 - sky_share) / (1.0 + 0.75 * r * away));
        for (uint l = 0u; l < point_lights; ++l) {
          float d1 = distance(world_q, P.light_pos[l].xyz);
          float potential = pow(saturate(1.0 - d1 / P.light_pos[l].w), 12.0);
          light_in += P.light_color[l].rgb * (potential * (1.0 - saturate(ds.full * 5.0)));
        }
        float sigma_t = max(ds.full * ext, 1e-7);
        sigma_prev = sigma_t;
        float tr = exp(-sigma_t * dt);
        vec3 s_in = light_in * (sigma_t * albedo);
        px.radiance += px.transmittance * (s_in - s_in * tr) / sigma_t;
        float before = px.transmittance;
        px.transmittance *= tr;
        if (px.first_hit > 1e5) px.first_hit = ts;
        if (before >= 0.5 && px.transmittance < 0.5) px.depth50 = ts;
      }
      px.profile_opacity = 1.0 - (1.0 - px.profile_opacity) * exp(-ds.raw_profile * ext * dt);
#if ABLATION == CLOUD_ABLATION_FULL
      if (ds.presence <= 0.0) step_len = max(step_len, absent_step);
#endif
    }
    t += step_len;
  }
}

void main() {
  // Reprojection (pc.sub.x = B > 1): this invocation marches pixel block * B + offset of the full-resolution
  // image and writes its result at `block` of the sub-sampled image (reconstruct.comp fills the rest).
  ivec2 block = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  int B = max(int(pc.sub.x), 1);
  if (any(greaterThanEqual(block * B, size))) return;
  ivec2 pixel = min(block * B + ivec2(pc.sub.yz), size - 1);
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = P.camera_pos.xyz;
  vec3 rd = view_ray_dir(P.inv_view_proj, ndc, ro);

  // Scene distance along the ray from the depth buffer; depth 0 is the cleared far plane (sky).
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_scene = 1e30;
  if (d > 0.0) {
    vec4 w = P.inv_view_proj * vec4(ndc, d, 1.0);
    t_scene = distance(w.xyz / w.w, ro);
  }
  float t_begin = 0.0, t_end = t_scene;
#if SEGMENT == CLOUD_SEGMENT_NEAR
  t_end = min(t_end, P.steps.x);
#elif SEGMENT == CLOUD_SEGMENT_FAR
  t_begin = P.steps.x;
#endif

  PixelData px;
  px.radiance = vec3(0.0);
  px.transmittance = 1.0;
  px.depth50 = 1e6;
  px.first_hit = 1e6;
  px.steps = 0.0;
  px.profile_opacity = 0.0;
  // Static hash: same every frame; animated: per frame. Pixel coordinates of the full-resolution grid.
  vec2 hash_pixel = uv * P.viewport.xy;
  float hash_static = pixel_hash(hash_pixel, 0u);
  float hash_animated = pixel_hash(hash_pixel, P.frame.x);

  // Instances in order of their entry distance (at most CLOUD_MAX_INSTANCES: a tiny insertion sort), and
  // every entry and exit along the ray: boxes may overlap (a hero cloud inside the cloudscape's box), so the
  // ray is marched interval by interval between these boundaries, each instance present in an interval
  // in entry order. Marching one instance's whole segment and then the next would add a far cloud of the
  // first behind a near wall of the second at full weight.
  uint n = min(P.frame.y, uint(CLOUD_MAX_INSTANCES));
  float enter[CLOUD_MAX_INSTANCES];
  float leave[CLOUD_MAX_INSTANCES];
  int order[CLOUD_MAX_INSTANCES];
  float cuts[2 * CLOUD_MAX_INSTANCES];
  uint n_cuts = 0u;
  for (uint i = 0u; i < n; ++i) {
    CloudInstanceParams inst = P.instances[i];
    vec3 ao = (inst.world_to_asset * vec4(ro, 1.0)).xyz;
    vec3 ad = mat3(inst.world_to_asset) * rd;
    vec2 seg = ray_box(ao, ad, inst.bounds_min.xyz, inst.bounds_max.xyz);
    bool hit = seg.x <= seg.y && seg.y > 0.0;
    enter[i] = hit ? max(seg.x, 0.0) : 1e30;
    leave[i] = hit ? seg.y : -1e30;
    order[i] = int(i);
    if (hit) {
      cuts[n_cuts++] = enter[i];
      cuts[n_cuts++] = leave[i];
    }
  }
  for (uint i = 1u; i < n; ++i)
    for (uint j = i; j > 0u && enter[order[j]] < enter[order[j - 1u]]; --j) {
      int tmp = order[j];
      order[j] = order[j - 1u];
      order[j - 1u] = tmp;
    }
  for (uint i = 1u; i < n_cuts; ++i)
    for (uint j = i; j > 0u && cuts[j] < cuts[j - 1u]; --j) {
      float tmp = cuts[j];
      cuts[j] = cuts[j - 1u];
      cuts[j - 1u] = tmp;
    }
  float t_front = 1.0;
  vec4 mean_noise = noise_mean();
#if SEGMENT == CLOUD_SEGMENT_FAR
  // The largest transmittance of the 4 half-resolution near texels around this pixel: conservative, the
  // far march stops only where every one of them is opaque.
  {
    ivec2 ns = textureSize(near_color, 0);
    vec2 np = uv * vec2(ns) - 0.5;
    ivec2 b = ivec2(floor(np));
    t_front = 0.0;
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) t_front = max(t_front, texelFetch(near_color, clamp(b + ivec2(k, j), ivec2(0), ns - 1), 0).a);
  }
#endif
  for (uint c = 0u; c + 1u < n_cuts; ++c) {
    float a = max(cuts[c], t_begin), b = min(cuts[c + 1u], t_end);
    if (b <= a) continue;
    uint present = 0u;
    for (uint k = 0u; k < n; ++k) present += enter[k] <= a && leave[k] >= b ? 1u : 0u;
    // Where boxes overlap, the interval goes in pieces (64 m near the camera, a quarter of the distance
    // beyond 256 m), each piece marched for every instance: ordering errors stay within a piece (levels
    // keep their assets' clouds apart, as the sample's cloudscape leaves room for the storm cloud). Where
    // all but one of the instances have no cloud within a distance of the piece's start (the second smallest
    // of their signed distances there), the piece reaches that far: only one instance's cloud can lie in it,
    // so nothing is out of order, and each piece costs every instance a call (issue 23: inside the storm
    // cloud, where the cloudscape leaves room for it, 64 m pieces cost the lair a third of its march).
    for (float p0 = a; p0 < b && px.transmittance * t_front >= P.march.z;) {
      float p1 = b;
      if (present > 1u) {
        vec3 w0 = ro + rd * p0;
        float d1 = 1e30, d2 = 1e30;
        for (uint k = 0u; k < n; ++k) {
          int i = order[k];
          if (enter[i] > a || leave[i] < b) continue;
          float d = instance_distance(i, w0);
          d2 = min(d2, max(d1, d));
          d1 = min(d1, d);
        }
        p1 = min(b, p0 + max(max(64.0, 0.25 * p0), d2));
      }
      for (uint k = 0u; k < n; ++k) {
        int i = order[k];
        if (enter[i] > a || leave[i] < b) continue;  // not in this interval
#if CLOUD_ASSET_SLOTS > 2
        if (P.instances[i].wind_offset.w > 1.5)
          march_instance(CLOUD_ASSET_2, field_tex_2, field_fair_tex_2, i, ro, rd, p0, p1, hash_animated, hash_static, t_front, mean_noise, px);
        else
#endif
#if CLOUD_ASSET_SLOTS > 1
        // A lane marching another slot's instance leaves this call's loop at once (lavapipe runs a loop
        // only while some lane is in it), so the calls cost about one march.
        if (P.instances[i].wind_offset.w > 0.5)
          march_instance(CLOUD_ASSET_1, field_tex_1, field_fair_tex_1, i, ro, rd, p0, p1, hash_animated, hash_static, t_front, mean_noise, px);
        else
#endif
          march_instance(CLOUD_ASSET_0, field_tex, field_fair_tex, i, ro, rd, p0, p1, hash_animated, hash_static, t_front, mean_noise, px);
      }
      p0 = p1;
    }
  }

  float depth = px.depth50 < 1e5 ? px.depth50 : px.first_hit;
  vec4 color = vec4(px.radiance, px.transmittance);
  if (P.frame.w == CLOUD_DEBUG_PROFILE) color = vec4(vec3(px.profile_opacity), 0.0);
  imageStore(out_color, block, color);
  imageStore(out_depth, block, vec4(depth, px.steps, min(t_end, 1e6), 0.0));
}
