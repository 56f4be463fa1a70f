// The 2.5D sky's density model (sky_layer.comp has its sources), shared by the march and the density
// probe (sky_layer_probe.comp): the parameter block, the map and noise bindings, the shell, the yield.
#ifndef CUMULO_SKY_LAYER_DENSITY_GLSL
#define CUMULO_SKY_LAYER_DENSITY_GLSL
#include "shared/sky_layer_params.h"
#include "clouds/cloud_math.glsl"
#include "engine/runtime_uniform.glsl"

layout(set = 0, binding = SKY_BINDING_PARAMS, std140) uniform SkyBlock { SkyLayerParams S; };
layout(set = 0, binding = SKY_BINDING_CLOUD_MAP) uniform sampler2D cloud_map;
layout(set = 0, binding = SKY_BINDING_BASE_NOISE) uniform sampler3D base_noise;
layout(set = 0, binding = SKY_BINDING_DETAIL_NOISE) uniform sampler3D detail_noise;
layout(set = 0, binding = SKY_BINDING_CURL) uniform sampler3D curl_noise;

// The 2015 Remap, unclamped (value_remap in cloud_math.glsl is the clamped one).
float remap(float v, float a, float b, float c, float d) { return c + (v - a) / (b - a) * (d - c); }

// The planet's centre is under the world origin; altitude above sea level of a world point.
vec3 planet_centre() { return vec3(0.0, -S.shell.z, 0.0); }
float altitude(vec3 p) { return length(p - planet_centre()) - S.shell.z; }

// Entry and exit of the ray in the sphere of radius r (x > y: a miss).
vec2 ray_sphere(vec3 ro, vec3 rd, float r) {
  vec3 oc = ro - planet_centre();
  float b = dot(oc, rd), c = dot(oc, oc) - r * r;
  float disc = b * b - c;
  if (disc < 0.0) return vec2(1e30, -1e30);
  float s = sqrt(disc);
  return vec2(-b - s, -b + s);
}

// The ray's first stretch inside the shell (inner..outer radius), clipped to [0, t_max]; x >= y: none.
vec2 shell_segment(vec3 ro, vec3 rd, float t_max) {
  vec2 outer = ray_sphere(ro, rd, S.shell.z + S.shell.y);
  vec2 inner = ray_sphere(ro, rd, S.shell.z + S.shell.x);
  float t0 = max(outer.x, 0.0), t1 = min(outer.y, t_max);
  if (t0 >= t1) return vec2(1.0, 0.0);
  if (inner.x < inner.y) {
    if (inner.x <= t0 && inner.y > t0) t0 = inner.y;          // starts inside the inner sphere: leave it first
    else if (inner.x > t0 && inner.x < t1) t1 = inner.x;      // enters the inner sphere: the stretch ends there
  }
  return vec2(t0, t1);
}

// Density scale of the voxel cloudscape's presence: 0 in a box's footprint within its heights, 1 beyond
// the fade outside the footprint (S.misc.x) or above the box's top (S.misc.w): a deck above the voxel
// clouds stays (two layers, no double counting), and where they share heights the layer hands over.
float yield_mask(vec3 p) {
  float m = 1.0;
  for (int i = 0; i < runtime_int(S.misc.y); ++i) {
    vec2 outside = max(max(S.yield_min[i].xz - p.xz, p.xz - S.yield_max[i].xz), vec2(0.0));
    float above = max(max(p.y - S.yield_max[i].y, S.yield_min[i].y - p.y), 0.0);
    m *= max(smoothstep(0.0, S.misc.x, length(outside)), smoothstep(0.0, S.misc.w, above));
  }
  return m;
}

// Height gradient of a cloud type (0 stratus, 0.5 stratocumulus, 1 cumulus) at height fraction h,
// grown toward a cumulonimbus tower by precipitation.
float height_gradient(float h, float type, float precip) {
  float stratus = value_remap(h, 0.0, 0.08, 0.0, 1.0) * value_remap(h, 0.15, 0.25, 1.0, 0.0);
  float stratocumulus = value_remap(h, 0.0, 0.15, 0.0, 1.0) * value_remap(h, 0.35, 0.55, 1.0, 0.0);
  float cumulus = value_remap(h, 0.0, 0.15, 0.0, 1.0) * value_remap(h, 0.6, 0.9, 1.0, 0.0);
  float g = type < 0.5 ? mix(stratus, stratocumulus, type * 2.0) : mix(stratocumulus, cumulus, type * 2.0 - 1.0);
  float cumulonimbus = value_remap(h, 0.0, 0.1, 0.0, 1.0) * value_remap(h, 0.9, 1.0, 1.0, 0.0);
  return mix(g, cumulonimbus, precip);
}

struct Weather {
  float coverage, type, precip;
};

Weather weather_at(vec3 p) {
  vec4 m = textureLod(cloud_map, (p.xz - S.wind.xy) / S.wind_dir.w, 0.0);
  Weather w;
  w.coverage = saturate(2.0 * m.r * S.weather.x);
  w.type = saturate(S.weather.y + m.b - 0.5);
  w.precip = saturate(2.0 * m.g * S.weather.z);
  w.coverage = mix(w.coverage, max(w.coverage, 0.7), w.precip);
  float k = smoothstep(S.horizon.x, S.horizon.y, length(p.xz - S.camera_pos.xz));
  w.coverage = mix(w.coverage, max(w.coverage, S.horizon.z), k);
  w.type = mix(w.type, S.horizon.w, k);
  return w;
}

// The cheap density at a world point (no detail erosion: light samples, empty space), before the yield;
// `c` keeps what the detail erosion needs so the full density does not compute it again.
struct SkyCoarse {
  float d;        // coarse density, before the yield
  float yield_m;  // yield_mask(p)
  float h;        // height fraction in the shell
  vec3 q;         // the noise position (wind-shifted)
};

SkyCoarse density_coarse(vec3 p) {
  SkyCoarse c;
  c.d = 0.0;
  c.h = saturate((altitude(p) - S.shell.x) / (S.shell.y - S.shell.x));
  c.q = p;
  c.yield_m = yield_mask(p);
  if (c.yield_m <= 0.0) return c;
  Weather w = weather_at(p);
  if (w.coverage <= 0.0) return c;
  float thickness = S.shell.y - S.shell.x;
  c.q = p - S.wind_dir.xyz * (S.wind.w + c.h * S.wind.z * thickness);
  vec4 b = textureLod(base_noise, c.q / S.shape.x, 0.0);
  float wfbm = b.g * 0.625 + b.b * 0.25 + b.a * 0.125;
  float base = remap(b.r, -(1.0 - wfbm), 1.0, 0.0, 1.0);
  base = saturate(base * height_gradient(c.h, w.type, w.precip));
  float cov = pow(w.coverage, value_remap(c.h, 0.7, 0.8, 1.0, mix(1.0, 0.5, S.weather.w)));
  c.d = saturate(remap(base, 1.0 - cov, 1.0, 0.0, 1.0)) * cov;
  return c;
}

// The full density from the coarse one: the detail erosion, then the yield.
float density_detail(SkyCoarse c) {
  if (c.d <= 0.0) return 0.0;
  vec3 curl = (textureLod(curl_noise, vec3(c.q.xz / S.shape.x * 4.0, 0.5), 0.0).rgb * 2.0 - 1.0) * S.shape.z;
  vec3 dn = textureLod(detail_noise, (c.q + curl * (1.0 - c.h)) / S.shape.y, 0.0).rgb;
  float dfbm = dn.r * 0.625 + dn.g * 0.25 + dn.b * 0.125;
  float modifier = mix(1.0 - dfbm, dfbm, saturate(c.h * 10.0));
  return saturate(remap(c.d, modifier * S.shape.w, 1.0, 0.0, 1.0)) * c.yield_m;
}

// Density at a world point; `cheap` leaves out the detail erosion (light samples, empty space).
float density(vec3 p, bool cheap) {
  SkyCoarse c = density_coarse(p);
  return cheap ? c.d * c.yield_m : density_detail(c);
}

#endif
