#version 450
// The path-traced reference of the cloudscape (issue 11; modules/clouds/render/reference_tracer.h): per
// pixel, R.settings.w unbiased samples of the radiance along the pixel's centre ray, added to the
// accumulation images. The medium is exactly the real-time march's: the same CloudParams block, the same
// up-rez sampler (cloud_common.glsl's sample_density, with the near-camera details and the noise mip of
// the distance to the camera, so the field is one fixed function of position for a frame).
//
//   free flight   delta tracking (Woodcock) through each instance's majorant grid (3D DDA over coarse
//                 cells, reference_majorant.comp); instances are independent media, so the first
//                 collision in their sum is the nearest of their own first collisions
//   transmittance ratio tracking with the same majorants, Russian roulette below 0.1
//   sun           next-event estimation at every vertex: phase x E x transmittance x terrain visibility
//   point lights  the same, intensity R.light_scale.x x the colour (lightning; 1/d^2 falloff)
//   sky           the environment (the atmosphere's sky radiance, latitude-longitude) where a path escapes;
//                 after the last allowed vertex, one more phase-sampled ray gathers it with its transmittance
//   terrain       an opaque Lambertian heightfield (the level's meshes rasterized from above) and an ocean
//                 plane; the camera ray ends at the raster depth, as the real-time march's does
//   bounces       at most R.settings.x scattering events per path (1: single scattering); Russian
//                 roulette on the throughput after 8
// Phase: the march's dual-lobe HG (sampled by lobe: weight 1), Jendersie & d'Eon 2023's approximate Mie
// (sampled from an HG mixture, weighted), or isotropic.
//
// The Envelope method's orographic clouds (ENVELOPE 1; envelope_density.glsl, its bindings at
// ENV_BINDING_REFERENCE_OFFSET) are a medium beside the instances: the march's density with its near detail, tracked
// texel by texel of its maps (2D DDA) with the majorant E.heights.w x E.wind.w (the up-rezzed density is at most the
// multiplier) where the ray is inside the texel's conservative column, 0 elsewhere.
//
// Defines: MEDIUM (0 the cloudscape, 1 the analytic box of ReferenceParams for tests), CLOUD_ASSET_SLOTS, ENVELOPE.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"
#include "shared/reference_params.h"
#include "engine/atmosphere_common.glsl"
#include "engine/view_ray.glsl"

#ifndef MEDIUM
#define MEDIUM 0
#endif
#ifndef ENVELOPE
#define ENVELOPE 0
#endif
#if ENVELOPE
#define ENV_BINDING_OFFSET ENV_BINDING_REFERENCE_OFFSET
#include "clouds/envelope_density.glsl"
#endif

layout(local_size_x = REF_LOCAL_SIZE, local_size_y = REF_LOCAL_SIZE) in;
layout(set = 0, binding = REF_BINDING_PARAMS, std140) uniform RefBlock { ReferenceParams R; };
#if MEDIUM == 0
layout(set = 0, binding = REF_BINDING_MAJORANT) uniform sampler3D majorant_tex;
#if CLOUD_ASSET_SLOTS > 1
layout(set = 0, binding = REF_BINDING_MAJORANT_1) uniform sampler3D majorant_tex_1;
#endif
#if CLOUD_ASSET_SLOTS > 2
layout(set = 0, binding = REF_BINDING_MAJORANT_2) uniform sampler3D majorant_tex_2;
#endif
#endif
layout(set = 0, binding = CLOUD_BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = REF_BINDING_TERRAIN) uniform sampler2D terrain_tex;
layout(set = 0, binding = REF_BINDING_ENV) uniform sampler2D env_tex;
layout(set = 0, binding = REF_BINDING_AERIAL) uniform sampler3D aerial_tex;
layout(set = 0, binding = REF_BINDING_ACCUM, rgba32f) uniform image2D accum_img;
layout(set = 0, binding = REF_BINDING_AUX, rgba32f) uniform image2D aux_img;

const float kFar = 1e7;
const int kMaxCells = 2048;     // DDA cells per instance and ray (a 64^3-cell grid is crossed in < 200)
const int kMaxEvents = 16384;   // tentative collisions per instance and ray (a bound, never reached in practice)

// ---- Random numbers: PCG (O'Neill 2014), one stream per pixel and sample -----------------------------
uint g_rng;
uint pcg_hash(uint v) {
  uint s = v * 747796405u + 2891336453u;
  uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
  return (w >> 22u) ^ w;
}
float rand01() {
  g_rng = g_rng * 747796405u + 2891336453u;
  uint w = ((g_rng >> ((g_rng >> 28u) + 4u)) ^ g_rng) * 277803737u;
  w = (w >> 22u) ^ w;
  return float(w >> 8) * (1.0 / 16777216.0);
}
float g_violations = 0.0;  // density above the majorant (must stay 0: the bound is conservative)

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }
bool has_flag(uint f) { return (R.flags.x & f) != 0u; }

// ---- The medium ----------------------------------------------------------------------------------
#if MEDIUM == 1
float medium_albedo() { return R.medium_max.w; }
// Delta tracking (ratio = false: the first real collision's t or -1) or ratio tracking (ratio = true:
// multiplies T) through the analytic box with its majorant R.medium.x.
float track(vec3 o, vec3 d, float tmax, bool ratio, inout float T) {
  vec2 seg = ray_box(o, d, R.medium_min.xyz, R.medium_max.xyz);
  float t = max(seg.x, 0.0), t1 = min(seg.y, tmax);
  if (!(t < t1)) return -1.0;
  float mu = R.medium.x;
  for (int k = 0; k < kMaxEvents; ++k) {
    t -= log(1.0 - rand01()) / mu;
    if (t >= t1) return -1.0;
    float s = R.medium_min.w;
    if (s > mu * 1.0001) g_violations += 1.0;
    if (ratio) {
      T *= max(1.0 - s / mu, 0.0);
      if (T < 0.1) {
        if (rand01() < 0.5) { T = 0.0; return -1.0; }
        T *= 2.0;
      }
    } else if (rand01() * mu < s) {
      return t;
    }
  }
  return -1.0;
}
float free_flight(vec3 o, vec3 d, float tmax) {
  float T = 1.0;
  return track(o, d, tmax, false, T);
}
float transmittance(vec3 o, vec3 d, float tmax) {
  float T = 1.0;
  track(o, d, tmax, true, T);
  return T;
}
#else
float medium_albedo() { return P.march.y; }
ivec3 majorant_size(CloudInstanceParams inst) {
#if CLOUD_ASSET_SLOTS > 2
  if (inst.wind_offset.w > 1.5) return textureSize(majorant_tex_2, 0);
#endif
#if CLOUD_ASSET_SLOTS > 1
  if (inst.wind_offset.w > 0.5) return textureSize(majorant_tex_1, 0);
#endif
  return textureSize(majorant_tex, 0);
}
ivec3 modeling_size(CloudInstanceParams inst) {
#if CLOUD_ASSET_SLOTS > 2
  if (inst.wind_offset.w > 1.5) return textureSize(modeling_tex_2, 0);
#endif
#if CLOUD_ASSET_SLOTS > 1
  if (inst.wind_offset.w > 0.5) return textureSize(modeling_tex_1, 0);
#endif
  return textureSize(modeling_tex, 0);
}
float majorant_at(CloudInstanceParams inst, ivec3 c) {
#if CLOUD_ASSET_SLOTS > 2
  if (inst.wind_offset.w > 1.5) return texelFetch(majorant_tex_2, c, 0).r;
#endif
#if CLOUD_ASSET_SLOTS > 1
  if (inst.wind_offset.w > 0.5) return texelFetch(majorant_tex_1, c, 0).r;
#endif
  return texelFetch(majorant_tex, c, 0).r;
}
// Extinction (1/m) of instance `inst` at world point x (asset point q): the march's sample exactly.
float instance_sigma(CloudInstanceParams inst, vec3 q, vec3 x) {
  float dist = distance(x, P.camera_pos.xyz);
  float mip = noise_mip(dist);
#if CLOUD_ASSET_SLOTS > 2
  if (inst.wind_offset.w > 1.5) return sample_density(CLOUD_ASSET_2, inst, q, dist, mip, true).full * P.march.x;
#endif
#if CLOUD_ASSET_SLOTS > 1
  if (inst.wind_offset.w > 0.5) return sample_density(CLOUD_ASSET_1, inst, q, dist, mip, true).full * P.march.x;
#endif
  return sample_density(CLOUD_ASSET_0, inst, q, dist, mip, true).full * P.march.x;
}
// One instance along o + d t, t in [0, tmax]: delta tracking (returns the first real collision, or -1)
// or ratio tracking (ratio: multiplies T, returns -1), cell by cell of its majorant grid.
float track_instance(int i, vec3 o, vec3 d, float tmax, bool ratio, inout float T) {
  CloudInstanceParams inst = P.instances[i];
  vec3 ao = (inst.world_to_asset * vec4(o, 1.0)).xyz;
  vec3 ad = mat3(inst.world_to_asset) * d;  // asset units per world metre
  vec3 bmin = inst.bounds_min.xyz, bmax = inst.bounds_max.xyz;
  vec2 seg = ray_box(ao, ad, bmin, bmax);
  float t = max(seg.x, 0.0), t1 = min(seg.y, tmax);
  if (!(t < t1)) return -1.0;
  ivec3 G = majorant_size(inst);
  // A cell is REF_MAJORANT_CELL voxels (the last one per axis may reach past the box, which clips the ray).
  vec3 cell = (bmax - bmin) / vec3(modeling_size(inst)) * float(REF_MAJORANT_CELL);
  vec3 gp = (ao + ad * t - bmin) / cell;  // grid coordinates at t
  vec3 gd = ad / cell;                    // grid units per world metre
  ivec3 c = clamp(ivec3(floor(gp)), ivec3(0), G - 1);
  ivec3 dir = ivec3(gd.x > 0.0 ? 1 : -1, gd.y > 0.0 ? 1 : -1, gd.z > 0.0 ? 1 : -1);
  vec3 t_next, t_delta;
  for (int a = 0; a < 3; ++a) {
    if (abs(gd[a]) < 1e-12) {
      t_next[a] = 1e30;
      t_delta[a] = 1e30;
    } else {
      float boundary = float(c[a] + (gd[a] > 0.0 ? 1 : 0));
      t_next[a] = t + (boundary - gp[a]) / gd[a];
      t_delta[a] = 1.0 / abs(gd[a]);
    }
  }
  float scale = inst.sun_dir.w * P.march.x;  // the instance's density and the extinction
  int events = 0;
  for (int k = 0; k < kMaxCells; ++k) {
    float tc = min(min(min(t_next.x, t_next.y), t_next.z), t1);
    float mu = majorant_at(inst, c) * scale;
    if (mu > 0.0) {
      for (; events < kMaxEvents; ++events) {
        t -= log(1.0 - rand01()) / mu;
        if (t >= tc) break;
        float s = instance_sigma(inst, ao + ad * t, o + d * t);
        if (s > mu * 1.0001) g_violations += 1.0;
        if (ratio) {
          T *= max(1.0 - s / mu, 0.0);
          if (T < 0.1) {
            if (rand01() < 0.5) {
              T = 0.0;
              return -1.0;
            }
            T *= 2.0;
          }
        } else if (rand01() * mu < s) {
          return t;
        }
      }
    }
    t = tc;  // memoryless: the next cell starts its own flights at its boundary
    if (t >= t1) break;
    if (t_next.x <= t_next.y && t_next.x <= t_next.z) {
      c.x += dir.x;
      t_next.x += t_delta.x;
    } else if (t_next.y <= t_next.z) {
      c.y += dir.y;
      t_next.y += t_delta.y;
    } else {
      c.z += dir.z;
      t_next.z += t_delta.z;
    }
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, G))) break;
  }
  return -1.0;
}
#if ENVELOPE
// The envelope along o + d t, t in [0, tmax]: delta or ratio tracking as track_instance, over the maps' texels.
float track_envelope(vec3 o, vec3 d, float tmax, bool ratio, inout float T) {
  float mu = E.heights.w * E.wind.w;
  float side = E.map.z * E.map.w;
  vec2 seg = ray_box(o, d, vec3(E.map.x, E.heights.x, E.map.y), vec3(E.map.x + side, E.heights.y, E.map.y + side));
  float t = max(seg.x, 0.0), t1 = min(seg.y, tmax);
  if (!(t < t1) || !(mu > 0.0)) return -1.0;
  int N = int(E.map.w);
  vec2 gp = (o.xz + d.xz * t - E.map.xy) / E.map.z;
  vec2 gd = d.xz / E.map.z;
  ivec2 c = clamp(ivec2(floor(gp)), ivec2(0), ivec2(N - 1));
  ivec2 dir = ivec2(gd.x > 0.0 ? 1 : -1, gd.y > 0.0 ? 1 : -1);
  vec2 t_next, t_delta;
  for (int a = 0; a < 2; ++a) {
    if (abs(gd[a]) < 1e-12) {
      t_next[a] = 1e30;
      t_delta[a] = 1e30;
    } else {
      float boundary = float(c[a] + (gd[a] > 0.0 ? 1 : 0));
      t_next[a] = t + (boundary - gp[a]) / gd[a];
      t_delta[a] = 1.0 / abs(gd[a]);
    }
  }
  int events = 0;
  for (int k = 0; k < 4 * kMaxCells; ++k) {
    float tc = min(min(t_next.x, t_next.y), t1);
    vec4 s = texelFetch(steps_tex, c, 0);  // x: conservative top, y: bottom (envelope_maps.h; none: x < y)
    float a = t, b = tc;
    if (abs(d.y) > 1e-9) {
      float ya = (s.y - o.y) / d.y, yb = (s.x - o.y) / d.y;
      a = max(a, min(ya, yb));
      b = min(b, max(ya, yb));
    } else if (o.y < s.y || o.y > s.x) {
      b = a;
    }
    if (s.x > s.y && a < b) {
      // The majorant holds on [a, b]; past b the next texel starts its flights afresh (memoryless).
      float tt = a;
      for (; events < kMaxEvents; ++events) {
        tt -= log(1.0 - rand01()) / mu;
        if (tt >= b) break;
        float sg = envelope_sample(o + d * tt, true).density * E.wind.w;
        if (sg > mu * 1.0001) g_violations += 1.0;
        if (ratio) {
          T *= max(1.0 - sg / mu, 0.0);
          if (T < 0.1) {
            if (rand01() < 0.5) {
              T = 0.0;
              return -1.0;
            }
            T *= 2.0;
          }
        } else if (rand01() * mu < sg) {
          return tt;
        }
      }
    }
    t = tc;
    if (t >= t1) break;
    if (t_next.x <= t_next.y) {
      c.x += dir.x;
      t_next.x += t_delta.x;
    } else {
      c.y += dir.y;
      t_next.y += t_delta.y;
    }
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(N)))) break;
  }
  return -1.0;
}
#endif
float free_flight(vec3 o, vec3 d, float tmax) {
  float best = tmax;
  bool hit = false;
  float T = 1.0;
  for (uint i = 0u; i < min(P.frame.y, uint(CLOUD_MAX_INSTANCES)); ++i) {
    float t = track_instance(int(i), o, d, best, false, T);
    if (t >= 0.0 && t < best) {
      best = t;
      hit = true;
    }
  }
#if ENVELOPE
  float te = track_envelope(o, d, best, false, T);
  if (te >= 0.0 && te < best) {
    best = te;
    hit = true;
  }
#endif
  return hit ? best : -1.0;
}
float transmittance(vec3 o, vec3 d, float tmax) {
  float T = 1.0;
  for (uint i = 0u; i < min(P.frame.y, uint(CLOUD_MAX_INSTANCES)) && T > 0.0; ++i) track_instance(int(i), o, d, tmax, true, T);
#if ENVELOPE
  if (T > 0.0) track_envelope(o, d, tmax, true, T);
#endif
  return T;
}
#endif

// ---- Phase functions -----------------------------------------------------------------------------
// Draine's phase function (Draine 2003), as Jendersie & d'Eon 2023 combine it with HG.
float draine(float cos_t, float g, float alpha) {
  float g2 = g * g;
  return (1.0 - g2) * (1.0 + alpha * cos_t * cos_t) /
         (4.0 * kPi * (1.0 + alpha * (1.0 + 2.0 * g2) / 3.0) * pow(max(1.0 + g2 - 2.0 * g * cos_t, kEpsilon), 1.5));
}
float phase_value(float cos_t) {
  int kind = int(R.settings.y);
  if (kind == REF_PHASE_MIE)
    return mix(henyey_greenstein(cos_t, R.mie.x), draine(cos_t, R.mie.y, R.mie.z), R.mie.w);
  if (kind == REF_PHASE_ISOTROPIC) return 1.0 / (4.0 * kPi);
  return dual_lobe_phase(cos_t);
}
// A unit vector at angle acos(cos_t) around `axis`, uniformly in azimuth.
vec3 around(vec3 axis, float cos_t) {
  float sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
  float phi = 2.0 * kPi * rand01();
  vec3 t = abs(axis.y) < 0.999 ? normalize(cross(axis, vec3(0.0, 1.0, 0.0))) : vec3(1.0, 0.0, 0.0);
  vec3 b = cross(axis, t);
  return normalize(axis * cos_t + (t * cos(phi) + b * sin(phi)) * sin_t);
}
float sample_hg_cos(float g) {
  float xi = rand01();
  if (abs(g) < 1e-3) return 1.0 - 2.0 * xi;
  float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
  return clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}
// A new direction after scattering from travel direction d; `weight` = phase / pdf.
vec3 sample_phase(vec3 d, out float weight) {
  int kind = int(R.settings.y);
  weight = 1.0;
  if (kind == REF_PHASE_ISOTROPIC) return around(d, 1.0 - 2.0 * rand01());
  if (kind == REF_PHASE_MIE) {
    // Proposal: the same mixture with HG in place of Draine (the ratio is bounded by (1 + alpha) / (1 + alpha / 3)).
    bool draine_lobe = rand01() < R.mie.w;
    float c = sample_hg_cos(draine_lobe ? R.mie.y : R.mie.x);
    float pdf = mix(henyey_greenstein(c, R.mie.x), henyey_greenstein(c, R.mie.y), R.mie.w);
    weight = phase_value(c) / max(pdf, 1e-8);
    return around(d, c);
  }
  // The dual lobe: pick a lobe with its weight; the pdf is then the phase itself.
  bool forward = rand01() < P.phase.z;
  return around(d, sample_hg_cos(forward ? P.phase.x : P.phase.y));
}

// ---- Surfaces: the terrain heightfield and the ocean plane ---------------------------------------
vec2 terrain_uv(vec2 xz) { return (xz - R.terrain.xy) / R.terrain.zw; }
float terrain_height(vec2 xz) {
  vec2 uv = terrain_uv(xz);
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return -1e9;
  return textureLod(terrain_tex, uv, 0.0).x;
}
vec3 terrain_normal(vec2 xz) {
  float e = R.terrain.z / float(textureSize(terrain_tex, 0).x);
  float hx = terrain_height(xz - vec2(e, 0.0)) - terrain_height(xz + vec2(e, 0.0));
  float hz = terrain_height(xz - vec2(0.0, e)) - terrain_height(xz + vec2(0.0, e));
  if (abs(hx) > 1e6 || abs(hz) > 1e6) return vec3(0.0, 1.0, 0.0);  // the heightfield's border
  return normalize(vec3(hx, 2.0 * e, hz));
}
// What a surface point is: albedo and normal (the ocean where the plane lies above the terrain).
void surface_at(vec3 x, out vec3 albedo, out vec3 n) {
  bool ocean = has_flag(REF_FLAG_OCEAN) && x.y <= R.terrain_range.w + 0.5 && terrain_height(x.xz) < R.terrain_range.w;
  if (ocean || !has_flag(REF_FLAG_TERRAIN)) {
    albedo = ocean ? R.ocean_albedo.rgb : vec3(0.0);
    n = vec3(0.0, 1.0, 0.0);
    return;
  }
  albedo = textureLod(terrain_tex, terrain_uv(x.xz), 0.0).yzw;
  n = terrain_normal(x.xz);
}
// The first surface along o + d t in (0, tmax), or -1: the ocean plane exactly, the heightfield marched
// over the stretch of the ray below its highest point (at most 384 steps of half a texel or more).
float ocean_hit(vec3 o, vec3 d, float tmax) {
  if (!has_flag(REF_FLAG_OCEAN) || d.y >= 0.0) return -1.0;
  float t = (R.terrain_range.w - o.y) / d.y;
  return t > 0.0 && t < tmax ? t : -1.0;
}
// `tmin`: rays leaving a surface skip its first two texels (the raster surface and the bilinear
// heightfield differ by up to a few metres; without this a point would shadow itself).
float surface_hit(vec3 o, vec3 d, float tmax, float tmin) {
  float best = ocean_hit(o, d, tmax);
  if (best >= 0.0) tmax = best;
  if (!has_flag(REF_FLAG_TERRAIN)) return best;
  vec3 lo = vec3(R.terrain.x, R.terrain_range.x - 1.0, R.terrain.y);
  vec3 hi = vec3(R.terrain.x + R.terrain.z, R.terrain_range.y, R.terrain.y + R.terrain.w);
  vec2 seg = ray_box(o, d, lo, hi);
  float texel = R.terrain.z / float(textureSize(terrain_tex, 0).x);
  float a = max(seg.x, tmin * texel), b = min(seg.y, tmax);
  if (!(a < b)) return best;
  float n = min(ceil((b - a) / (0.5 * texel)), 384.0);
  float dt = (b - a) / max(n, 1.0);
  float prev_t = a;
  float prev_h = o.y + d.y * a - terrain_height(o.xz + d.xz * a);
  if (prev_h < 0.0) return a;
  for (float k = 1.0; k <= n; k += 1.0) {
    float t = a + dt * k;
    float h = o.y + d.y * t - terrain_height(o.xz + d.xz * t);
    if (h < 0.0) return prev_t + (t - prev_t) * prev_h / (prev_h - h);
    prev_t = t;
    prev_h = h;
  }
  return best;
}
float surface_visibility(vec3 o, vec3 d, float tmax, float tmin) { return surface_hit(o, d, tmax, tmin) < 0.0 ? 1.0 : 0.0; }

// ---- Light ---------------------------------------------------------------------------------------
vec3 sky_radiance(vec3 d) {
  if (!has_flag(REF_FLAG_SKY)) return vec3(0.0);
  if (R.medium.y >= 0.0) return d.y < 0.0 && R.medium.z > 0.0 ? vec3(0.0) : vec3(R.medium.y);  // (z: the upper hemisphere only)
  vec2 uv = vec2(atan(d.z, d.x) / (2.0 * kPi) + 0.5, 0.5 - asin(clamp(d.y, -1.0, 1.0)) / kPi);
  return textureLod(env_tex, uv, 0.0).rgb * R.env.x;
}
// Direct light at x arriving along each light's direction, weighted by `response(cos)`: the phase
// function in the medium (surface = false), or albedo / pi x the cosine on a surface of normal n.
vec3 direct_light(vec3 x, vec3 d, bool surface, vec3 n, vec3 albedo) {
  vec3 L = vec3(0.0);
  if (has_flag(REF_FLAG_SUN)) {
    vec3 l = P.sun_dir.xyz;
    float w = surface ? max(dot(n, l), 0.0) / kPi : phase_value(dot(d, l));
    if (w > 0.0) {
      vec3 start = surface ? x + n * 0.5 : x;
      float vis = surface_visibility(start, l, kFar, surface ? 2.0 : 0.0);
      if (vis > 0.0) L += (surface ? albedo : vec3(1.0)) * P.sun_color.rgb * (w * vis * transmittance(start, l, kFar));
    }
  }
  for (uint k = 0u; k < R.flags.z; ++k) {
    vec3 to = P.light_pos[k].xyz - x;
    float dist = length(to);
    vec3 l = to / max(dist, 1e-3);
    float w = surface ? max(dot(n, l), 0.0) / kPi : phase_value(dot(d, l));
    if (w <= 0.0) continue;
    vec3 start = surface ? x + n * 0.5 : x;
    float T = transmittance(start, l, dist) * surface_visibility(start, l, dist, surface ? 2.0 : 0.0);
    L += (surface ? albedo : vec3(1.0)) * P.light_color[k].rgb * (R.light_scale.x * w * T / max(dist * dist, 1.0));
  }
  return L;
}

// ---- The path -------------------------------------------------------------------------------------
// `t_scene`: where the camera ray meets the raster geometry (1e30: nothing). `view_T`: the camera ray's
// transmittance through the clouds up to there (one ratio-tracking estimate).
vec3 trace(vec3 o, vec3 d, float t_scene, vec2 uv, out float view_T) {
  vec3 L = vec3(0.0), beta = vec3(1.0);
  int max_vertices = max(int(R.settings.x), 1);
  view_T = transmittance(o, d, min(t_scene, kFar));
  bool from_surface = false;
  for (int v = 0; v <= max_vertices; ++v) {
    bool camera_ray = v == 0;
    float ts;
    if (camera_ray) {
      // The raster geometry's depth, else the ocean plane (drawn by the sky pass, not in the depth).
      ts = t_scene < 1e29 ? t_scene : ocean_hit(o, d, kFar);
    } else {
      ts = surface_hit(o, d, kFar, from_surface ? 2.0 : 0.0);
    }
    float tc = free_flight(o, d, ts >= 0.0 ? ts : kFar);
    float t_vertex = tc >= 0.0 ? tc : ts;
    if (t_vertex < 0.0) {
      L += beta * sky_radiance(d);  // escaped (the camera ray: the sky itself)
      break;
    }
    if (camera_ray && has_flag(REF_FLAG_AERIAL)) {
      // The air between the camera and the first vertex: the same froxels the real-time composite uses.
      vec4 ap = atm_aerial_lookup(aerial_tex, uv, t_vertex * 0.001);
      L += ap.rgb;
      beta *= ap.a;
    }
    vec3 x = o + d * t_vertex;
    bool surface = tc < 0.0;
    vec3 albedo = vec3(medium_albedo()), n = vec3(0.0, 1.0, 0.0);
    if (surface) {
      surface_at(x, albedo, n);
      if (dot(n, d) > 0.0) n = -n;
    } else {
      beta *= albedo;  // sigma_s / sigma_t at a real collision
    }
    L += beta * direct_light(x, d, surface, n, albedo);
    if (v + 1 >= max_vertices) {
      // The last vertex allowed: one more ray for the sky light it scatters, with its transmittance.
      float w = 1.0;
      vec3 nd;
      if (surface) {
        nd = around(n, sqrt(rand01()));  // cosine-weighted: albedo / pi x cos / pdf = albedo
        w = albedo.x > 0.0 || albedo.y > 0.0 || albedo.z > 0.0 ? 1.0 : 0.0;
        beta *= albedo;
      } else {
        nd = sample_phase(d, w);
      }
      vec3 start = surface ? x + n * 0.5 : x;
      if (w > 0.0 && surface_visibility(start, nd, kFar, surface ? 2.0 : 0.0) > 0.0) L += beta * w * sky_radiance(nd) * transmittance(start, nd, kFar);
      break;
    }
    from_surface = surface;
    if (surface) {
      beta *= albedo;
      d = around(n, sqrt(rand01()));
      o = x + n * 0.5;
    } else {
      float w;
      d = sample_phase(d, w);
      beta *= w;
      o = x;
    }
    if (v >= 8) {
      float q = clamp(max(beta.x, max(beta.y, beta.z)), 0.05, 1.0);
      if (rand01() > q) break;
      beta /= q;
    }
    if (max(beta.x, max(beta.y, beta.z)) <= 0.0) break;
  }
  return L;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(accum_img);
  if (any(greaterThanEqual(pixel, size))) return;
  vec2 uv = (vec2(pixel) + 0.5) / vec2(size);
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = P.camera_pos.xyz;
  vec3 rd = view_ray_dir(P.inv_view_proj, ndc, ro);
  float t_scene = 1e30;
  if (has_flag(REF_FLAG_SCENE_DEPTH)) {
    float depth = textureLod(scene_depth, uv, 0.0).r;
    if (depth > 0.0) {
      vec4 w = P.inv_view_proj * vec4(ndc, depth, 1.0);
      t_scene = distance(w.xyz / w.w, ro);
    }
  }
  vec4 sum = vec4(0.0);
  float sum_T = 0.0;
  uint first = uint(R.settings.z), count = uint(R.settings.w);
  for (uint s = 0u; s < count; ++s) {
    g_rng = pcg_hash(uint(pixel.x) + pcg_hash(uint(pixel.y) + pcg_hash(first + s + pcg_hash(R.flags.y))));
    float view_T;
    vec3 L = trace(ro, rd, t_scene, uv, view_T);
    if (any(isnan(L)) || any(isinf(L))) L = vec3(0.0);
    sum += vec4(L, luminance(L) * luminance(L));
    sum_T += view_T;
  }
  // The first dispatch of an accumulation starts it (no clear pass needed).
  bool restart = first == 0u;
  imageStore(accum_img, pixel, (restart ? vec4(0.0) : imageLoad(accum_img, pixel)) + sum);
  imageStore(aux_img, pixel, (restart ? vec4(0.0) : imageLoad(aux_img, pixel)) + vec4(sum_T, float(count), g_violations, 0.0));
}
