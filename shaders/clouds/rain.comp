#version 450
// Localized rain (issue 9): a column of rain under each precipitating cloud (Cloudscape "rain"), from the
// cloud base down to the ground, drawn over the scene after the clouds. The column is a thin medium
// (extinction intensity x 1.5 per km: heavy rain hides a mountain a few km off) whose density is
// modulated by the rain cells across it (value noise at 320 m and 120 m: heavier under some, a ragged edge) and by
// falling streaks: world-space columns of drops on a 1.5 m grid, each with its own phase,
// falling at 9 m/s, so nearby rays that share a drop column see a vertical streak and far ones average
// to a grey curtain. Eight samples per ray through the column, jittered per pixel; clipped by the scene
// depth; behind a cloud's half-opacity depth it is seen through the cloud's transmittance. Dispatched over
// the columns' screen rectangle (CloudEffectsPush::rect).
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "engine/runtime_uniform.glsl"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_FX_PARAMS, std140) uniform EffectsBlock { CloudEffectsParams F; };
layout(set = 0, binding = CLOUD_BINDING_FX_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = CLOUD_BINDING_FX_CLOUDS) uniform sampler2D cloud_color;
layout(set = 0, binding = CLOUD_BINDING_FX_CLOUD_DEPTH) uniform sampler2D cloud_depth;
layout(set = 0, binding = CLOUD_BINDING_FX_HDR, rgba16f) uniform image2D hdr;
layout(push_constant) uniform Push { CloudEffectsPush pc; };

float hash12(vec2 p) {
  vec3 p3 = fract(vec3(p.xyx) * 0.1031);
  p3 += dot(p3, p3.yzx + 33.33);
  return fract((p3.x + p3.y) * p3.z);
}

// 0..1: a falling drop streak at p (about 0.8 m long every 6 m of a drop column).
float streak(vec3 p, float time) {
  vec2 cell = floor(p.xz / 1.5);
  float h = hash12(cell);
  vec2 centre = (cell + 0.25 + 0.5 * vec2(h, fract(h * 7.13))) * 1.5;
  float lateral = 1.0 - smoothstep(0.0, 0.5, distance(p.xz, centre));
  float phase = fract((p.y + time * 9.0 + h * 60.0) / 6.0);
  return lateral * smoothstep(0.0, 0.05, phase) * (1.0 - smoothstep(0.08, 0.14, phase));
}

// Smooth value noise on a unit lattice, 0..1.
float value_noise(vec2 p) {
  vec2 i = floor(p), f = fract(p);
  f = f * f * (3.0 - 2.0 * f);
  return mix(mix(hash12(i), hash12(i + vec2(1.0, 0.0)), f.x), mix(hash12(i + vec2(0.0, 1.0)), hash12(i + vec2(1.0)), f.x), f.y);
}

// The rain cells across a column, 0..1 (two octaves, 320 m and 120 m): a shower falls from the cloud's cells, heavier
// under some than others, so the curtain varies across and its edge is ragged rather than a cylinder's straight side.
float rain_cells(vec2 q) { return 0.65 * value_noise(q / 320.0) + 0.35 * value_noise(q / 120.0 + 17.0); }

// Ray against the vertical cylinder (axis through c.xz, radius r) between y0 and y1: (t_in, t_out).
vec2 ray_column(vec3 ro, vec3 rd, vec3 c, float r, float y0, float y1) {
  vec2 o = ro.xz - c.xz, d = rd.xz;
  float a = dot(d, d), b = dot(o, d), k = dot(o, o) - r * r;
  vec2 t = vec2(-1e30, 1e30);
  if (a > 1e-8) {
    float disc = b * b - a * k;
    if (disc < 0.0) return vec2(1.0, 0.0);
    float sq = sqrt(disc);
    t = vec2((-b - sq) / a, (-b + sq) / a);
  } else if (k > 0.0) {
    return vec2(1.0, 0.0);
  }
  if (abs(rd.y) > 1e-6) {
    float ta = (y0 - ro.y) / rd.y, tb = (y1 - ro.y) / rd.y;
    t = vec2(max(t.x, min(ta, tb)), min(t.y, max(ta, tb)));
  } else if (ro.y < y0 || ro.y > y1) {
    return vec2(1.0, 0.0);
  }
  return t;
}

void main() {
  ivec2 pixel = pc.rect.xy + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(gl_GlobalInvocationID.xy, uvec2(pc.rect.zw))) || any(greaterThanEqual(pixel, ivec2(F.viewport.xy))))
    return;
  vec2 uv = (vec2(pixel) + 0.5) * F.viewport.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = F.camera_pos.xyz + runtime_zero();  // engine/runtime_uniform.glsl: much-used uniforms
  vec3 rd = view_ray_dir(F.inv_view_proj, ndc, ro);
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_scene = 1e30;
  if (d > 0.0) {
    vec4 w = F.inv_view_proj * vec4(ndc, d, 1.0);
    t_scene = distance(w.xyz / w.w, ro);
  }
  float cloud_t = 1.0, cloud_d = 1e30;
  if (F.misc.y + runtime_zero() > 0.5) {
    cloud_t = textureLod(cloud_color, uv, 0.0).a;
    cloud_d = textureLod(cloud_depth, uv, 0.0).x;
  }
  float time = F.camera_pos.w + runtime_zero();
  float jitter = hash12(vec2(pixel) + fract(time) * 17.0);
  float transmittance = 1.0;
  for (uint k = 0u; k < runtime_uint(F.counts.y); ++k) {
    vec4 col = F.rain_column[k];
    vec2 seg = ray_column(ro, rd, col.xyz, col.w, F.rain_params[k].y, col.y);
    float t0 = max(seg.x, 0.0), t1 = min(seg.y, t_scene);
    if (t1 <= t0) continue;
    float sigma = F.rain_params[k].x * 0.0015;
    float len = t1 - t0, dt = len / 8.0;
    float od = 0.0;
    for (int j = 0; j < 8; ++j) {
      vec3 p = ro + rd * (t0 + (float(j) + jitter) * dt);
      // Thinner toward the column's edge, which the cells move in and out (a ragged curtain, not a hard cylinder),
      // and denser under the heavier cells.
      float cells = rain_cells(p.xz - col.xz + float(k) * 731.0);
      float r = distance(p.xz, col.xz) / col.w + 0.45 * (0.5 - cells);
      float edge = 1.0 - smoothstep(0.3, 0.95, r);
      od += sigma * edge * mix(0.25, 1.75, cells) * (0.35 + 2.5 * streak(p, time)) * dt;
    }
    float tr = exp(-od);
    // Seen through the cloud's transmittance where the cloud stands in front of the column.
    transmittance *= cloud_d < t0 ? mix(1.0, tr, cloud_t) : tr;
  }
  if (transmittance >= 1.0) return;
  vec4 c0 = imageLoad(hdr, pixel);
  imageStore(hdr, pixel, vec4(mix(F.rain_light.rgb, c0.rgb, transmittance), c0.a));
}
