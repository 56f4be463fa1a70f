#version 450
// The weather-driven 2.5D sky beyond and above the voxel cloudscape (issue 10; the "Vertical Profile"
// method of the 2023 talk's table, i.e. the 2015 talk, seed 004, and the 2017 talk, seed 001).
//
// A spherical shell (S.shell: 1500-4000 m above sea level on a planet of radius S.shell.z centred under
// the world origin, so clouds descend into the horizon) is ray-marched within S.shell.w (35 km, 2015:
// "within a 35,000 meter radius around the player"):
//   cloud map (R coverage, G precipitation, B type; 0.5 = the weather state's value, 0 R = a hole):
//     coverage = saturate(2 R x state coverage), type = saturate(state type + B - 0.5),
//     precipitation = saturate(2 G x state precipitation) (2015: "transitions the map ... to cumulonimbus
//     clouds at 70% coverage"), cumulus bias toward the horizon (2015: "Starting at a distance of
//     15,000 meters we start transitioning to cumulus clouds at around 50% coverage");
//   height gradient by type (stratus, stratocumulus, cumulus; cumulonimbus with precipitation);
//   base = Remap(PerlinWorley, -(1 - Worley fBm), 1, 0, 1) x gradient (2015);
//   coverage as erosion: Remap(base, 1 - coverage, 1, 0, 1) x coverage, coverage raised to
//     Remap(height, 0.7, 0.8, 1, lerp(1, 0.5, anvil bias)) first (2017's anvil bias);
//   detail: Worley fBm distorted by curl noise, inverted toward the bottoms (2015: "If you invert the
//     Worley noise at the base of the clouds you get some nice whispy shapes"), eroding the edges;
//   wind: the map drifts, the noise scrolls, tops lean downwind by the height skew.
// Yield: the density fades to 0 over S.misc.x metres outside the footprint of every voxel cloudscape
// box (S.yield_*), so the voxel clouds stand alone where they are and the layer shows no edge.
// Lighting, as the voxel clouds: dual-lobe HG x Beer-Lambert over 5 cone samples toward the sun and a
// far one (2015: "we sample 6 times in a cone toward the sun ... The last sample is placed far away"),
// a multiple-scattering term, ambient growing with height (2015: "Ambient sky contribution increases
// over height"); energy-conserving integration. Then the 2D high layers (cirrus, alto) at S.high.y,
// scrolling (2015: "tiling and scrolling at different speeds and directions above the volumetric clouds").
// Steps: 64 looking up to 128 at the horizon (2015), taken the talk's way: cheap samples (no detail, no
// light) at a larger step find the stretch of the ray that holds cloud, and full samples march it from one
// cheap step before to one after (2015: "we do these cheaper samples at a larger step size until we hit a
// cloud isosurface ... we always take a step backward"); on a CPU device empty sky costs the cheap part only.
// The cheap step is 4 full steps and the full samples go in fours sharing one light sample at their middle
// (issue 23: the light samples were half the layer's cost on lavapipe; twice the cheap step and pairs cost
// 4.7 ms in the mixed view, this 3.6 ms (the passes' fastest frames), the picture 43-46 dB from it at 320x180).
// Run on one pixel of each 4x4 block of a half-resolution target per frame and reprojected (reconstruct.comp):
// 2015's 1 of 16.
// VOXEL_OCCLUSION 1 (issue 23): after the voxel clouds' march, a pixel they hide (opaque over its footprint, that
// opacity reached in front of the shell) is not marched: it keeps its last value, reprojected as a direction, so the
// reconstruction's neighbours and clamp boxes see what they saw (inside the storm cloud the layer cost 5.5 ms of a
// frame that could not show it).
#extension GL_GOOGLE_include_directive : require
#include "clouds/sky_layer_density.glsl"
#include "shared/cloud_params.h"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = SKY_BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = SKY_BINDING_OUT_COLOR, rgba16f) uniform writeonly image2D out_color;
layout(set = 0, binding = SKY_BINDING_OUT_DEPTH, rgba32f) uniform writeonly image2D out_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };  // sub.w: the layer's last frame is valid

#ifndef VOXEL_OCCLUSION
#define VOXEL_OCCLUSION 0
#endif
#if VOXEL_OCCLUSION
layout(set = 0, binding = SKY_BINDING_VOXEL_COLOR) uniform sampler2D voxel_color;
layout(set = 0, binding = SKY_BINDING_VOXEL_DEPTH) uniform sampler2D voxel_depth;
layout(set = 0, binding = SKY_BINDING_HISTORY) uniform sampler2D history_tex;
// Below this transmittance (the march stops at 0.01) the composite lets through 2 % of the layer, and what it lets
// through is the layer's last value, not nothing: a still camera's picture is the same.
const float kHidden = 0.02;
bool hidden_by_voxels(vec2 uv, float shell_entry) {
  vec4 a = textureGather(voxel_color, uv, 3);
  vec4 d = textureGather(voxel_depth, uv, 0);
  return max(max(a.x, a.y), max(a.z, a.w)) < kHidden && max(max(d.x, d.y), max(d.z, d.w)) < shell_entry;
}
// The layer's last value in direction rd (none without a valid last frame or off its screen).
vec4 last_value(vec3 rd) {
  vec4 prev = S.prev_view_proj * vec4(rd, 0.0);
  if (pc.sub.w < 0.5 || prev.w <= 0.0) return vec4(0.0, 0.0, 0.0, 1.0);
  vec2 prev_uv = prev.xy / prev.w * 0.5 + 0.5;
  if (any(lessThan(prev_uv, vec2(0.0))) || any(greaterThan(prev_uv, vec2(1.0)))) return vec4(0.0, 0.0, 0.0, 1.0);
  vec2 prev_px = prev_uv * pc.target.xy - 0.5;
  vec2 snapped = round(prev_px);  // a still camera reads its own texel, unblurred
  vec2 fetch_uv = all(lessThan(abs(prev_px - snapped), vec2(0.01))) ? (snapped + 0.5) * pc.target.zw : prev_uv;
  return textureLod(history_tex, fetch_uv, 0.0);
}
#endif


// A fixed cone of 5 unit offsets around the light direction (2015: "6 times in a cone toward the sun").
const vec3 kCone[5] = vec3[](vec3(0.38, -0.60, 0.24), vec3(-0.55, 0.16, -0.41), vec3(0.12, 0.73, -0.28),
                             vec3(-0.25, -0.34, 0.69), vec3(0.67, 0.21, 0.45));

float light_optical_depth(vec3 p, vec3 l) {
  float seg = S.march.w, sum = 0.0, t = 0.0;
  for (int k = 0; k < 5; ++k) {
    float len = seg * float(k + 1);
    vec3 q = p + l * (t + 0.5 * len) + kCone[k] * (0.3 * float(k + 1) * seg);
    sum += density(q, true) * len;
    t += len;
  }
  sum += density(p + l * (t + 6.0 * seg), true) * 3.0 * seg;  // far: shadows of distant clouds
  return sum * S.march.x;
}

// The 2D high layers: cirrus (streaks) and alto (patches), tiling and scrolling at their own drift.
vec4 high_layers(vec3 ro, vec3 rd, float t_max) {
  vec2 hit = ray_sphere(ro, rd, S.shell.z + S.high.y);
  float t = hit.x > 0.0 ? hit.x : hit.y;
  if (S.high.x <= 0.0 || t <= 0.0 || t > t_max) return vec4(0.0, 0.0, 0.0, 1e6);
  vec3 p = ro + rd * t;
  vec2 uv_c = (p.xz + S.high_scroll.xy) / S.high.z;
  vec2 uv_a = (p.xz + S.high_scroll.zw) / (S.high.z * 0.5);
  float cirrus = textureLod(base_noise, vec3(uv_c.x, 0.37, uv_c.y * 0.25), 0.0).g;  // stretched: streaks
  float alto = textureLod(base_noise, vec3(uv_a.x, 0.71, uv_a.y), 0.0).r;
  float c = saturate(remap(cirrus, 1.0 - S.high.x, 1.0, 0.0, 1.0));
  float a = saturate(remap(alto, 1.0 - 0.6 * S.high.x, 1.0, 0.0, 1.0)) * 0.6;
  float alpha = saturate((c + a) * S.high.w) * smoothstep(0.0, 0.08, rd.y);
  return vec4(alpha, 0.0, 0.0, t);
}

// The near fade (S.sun_dir.w, the camera's: sky_layer.cpp): a camera in or near the shell sees the layer from that
// distance on, fully from twice it. Read through runtime_zero(): it changes as the camera moves, and lavapipe would
// inline it in the branch below and compile the shader again every frame (runtime_uniform.glsl).
float g_near = 0.0;
// A full sample at step i (distance t): none past the stretch's end or the shell's.
float full_density(vec3 p, float t, int i, int i_end, float t_end) {
  SkyCoarse c = density_coarse(p);
  float fade = g_near > 0.0 ? smoothstep(g_near, 2.0 * g_near, t) : 1.0;
  return c.d * c.yield_m > 0.0 && t < t_end && i < i_end ? density_detail(c) * fade : 0.0;
}

void main() {
  ivec2 block = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  int B = max(int(pc.sub.x), 1);
  if (any(greaterThanEqual(block * B, size))) return;
  ivec2 pixel = min(block * B + ivec2(pc.sub.yz), size - 1);
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = S.camera_pos.xyz;
  vec3 rd = view_ray_dir(S.inv_view_proj, ndc, ro);
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_max = S.shell.w;
  if (d > 0.0) {
    vec4 w = S.inv_view_proj * vec4(ndc, d, 1.0);
    t_max = min(t_max, distance(w.xyz / w.w, ro));
  }

  vec3 radiance = vec3(0.0);
  float transmittance = 1.0, depth50 = 1e6, steps = 0.0;
  vec3 l = normalize(S.sun_dir.xyz);
  float mu = dot(rd, l);
  float phase = mix(henyey_greenstein(mu, S.phase.y), henyey_greenstein(mu, S.phase.x), S.phase.z);
  vec2 seg = shell_segment(ro, rd, t_max);
  g_near = S.sun_dir.w + runtime_zero();
  seg.x = max(seg.x, g_near);
#if VOXEL_OCCLUSION
  if (seg.x < seg.y && hidden_by_voxels(uv, seg.x)) {
    imageStore(out_color, block, last_value(rd));
    imageStore(out_depth, block, vec4(1e6, 0.0, 0.0, 0.0));
    return;
  }
#endif
  if (seg.x < seg.y) {
    float n = mix(S.march.z, S.march.y, saturate(abs(rd.y)));
    float dt = (seg.y - seg.x) / n;
    float t0 = seg.x + dt * pixel_hash(vec2(pixel), uint(S.misc.z));
    // The cheap march: where along the ray the cloud is ...
    int first = int(n), last = -1;
    for (int i = 0; i < int(n); i += 4) {
      float t = t0 + dt * float(i);
      if (t >= seg.y) break;
      SkyCoarse c = density_coarse(ro + rd * t);
      if (c.d * c.yield_m > 0.0) {
        first = min(first, i);
        last = i;
      }
    }
    // ... and full samples march that stretch at the step, from one cheap step before it to one after, in fours
    // that share one light sample (at their middle): the light's optical depth changes over a cone of 15 light
    // steps, far more slowly than the density over four view steps. Fours start at a multiple of 4, so the lanes
    // of a group stay in step with each other.
    int i_end = min(last + 4, int(n));
    for (int i = max(first - 4, 0) & ~3; i < i_end; i += 4) {
      float t = t0 + dt * float(i);
      if (t >= seg.y || transmittance < 0.01) break;
      vec3 p = ro + rd * t;
      vec4 dq;
      dq.x = full_density(p, t, i, i_end, seg.y);
      dq.y = full_density(p + rd * dt, t + dt, i + 1, i_end, seg.y);
      dq.z = full_density(p + rd * (2.0 * dt), t + 2.0 * dt, i + 2, i_end, seg.y);
      dq.w = full_density(p + rd * (3.0 * dt), t + 3.0 * dt, i + 3, i_end, seg.y);
      steps += 4.0;
      if (any(greaterThan(dq, vec4(0.0)))) {
        vec3 pm = p + rd * (1.5 * dt);
        float hf = saturate((altitude(pm) - S.shell.x) / (S.shell.y - S.shell.x));
        float od = light_optical_depth(pm, l);
        vec3 light_in = S.sun_color.rgb * (exp(-od) * phase + S.phase.w * exp(-od * 0.25) * 0.5 / (4.0 * kPi));
        light_in += S.ambient_color.rgb * mix(0.35, 1.0, hf);
        for (int k = 0; k < 4; ++k) {
          float dens = dq[k];
          if (dens <= 0.0) continue;  // another of the four holds the cloud
          float sigma_t = max(dens * S.march.x, 1e-7);
          float tr = exp(-sigma_t * dt);
          vec3 s_in = light_in * sigma_t;
          radiance += transmittance * (s_in - s_in * tr) / sigma_t;
          float before = transmittance;
          transmittance *= tr;
          if (before >= 0.5 && transmittance < 0.5) depth50 = t + dt * float(k);
        }
      }
    }
  }
  vec4 hl = high_layers(ro, rd, t_max);
  if (hl.x > 0.0) {
    vec3 c = S.sun_color.rgb * henyey_greenstein(mu, 0.6) * 0.6 + S.ambient_color.rgb;
    radiance += transmittance * hl.x * c;
    float before = transmittance;
    transmittance *= 1.0 - hl.x;
    if (before >= 0.5 && transmittance < 0.5) depth50 = hl.w;
  }
  if (depth50 > 1e5 && transmittance < 1.0) depth50 = seg.x < seg.y ? 0.5 * (seg.x + seg.y) : hl.w;
  imageStore(out_color, block, vec4(radiance, transmittance));
  imageStore(out_depth, block, vec4(depth50, steps, 0.0, 0.0));
}
