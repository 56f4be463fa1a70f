#version 450
// Sky-view LUT (Hillaire 2020 section 5.3): the sky's radiance seen from the camera's altitude, per
// azimuth (from the sun's) and elevation (dense at the horizon, atmosphere_common.glsl), single scattering
// of the sun and the moon plus psi_ms, the ground lit below the horizon; 30 steps growing with the square
// of the index (the air is densest near the viewer).
#extension GL_GOOGLE_include_directive : require
#include "engine/atmosphere_common.glsl"
#include "engine/runtime_uniform.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ATMOSPHERE_PARAMS_BINDING, std140) uniform AtmosphereBlock { AtmosphereGpuParams A; };
layout(set = 0, binding = ATMOSPHERE_TRANSMITTANCE_BINDING) uniform sampler2D transmittance_lut;
layout(set = 0, binding = ATMOSPHERE_MS_BINDING) uniform sampler2D ms_lut;
layout(set = 0, binding = ATMOSPHERE_OUT_BINDING, rgba16f) uniform writeonly image2D lut;

vec3 scatter(vec3 dir, vec3 light, float irradiance, float r, float t_max, bool ground) {
  if (!(irradiance > 0.0)) return vec3(0.0);
  vec3 pos = vec3(0.0, r, 0.0);
  float nu = dot(dir, light);
  float pr = atm_rayleigh_phase(nu), pm = atm_mie_phase(A.rayleigh.w, nu);
  const int kSteps = 30;
  vec3 L = vec3(0.0), T = vec3(1.0);
  float t0 = 0.0;
  for (int s = 0; s < kSteps; ++s) {
    float t1 = t_max * float((s + 1) * (s + 1)) / float(kSteps * kSteps);
    float dt = t1 - t0, t = 0.5 * (t0 + t1);
    t0 = t1;
    vec3 q = pos + dir * t;
    float rq = length(q), h = rq - A.radii.x, mu_s = dot(q, light) / rq;
    vec3 sr = atm_rayleigh_scattering(A, h);
    float sm = atm_mie_scattering(A, h);
    vec3 ext = atm_extinction(A, h);
    vec3 ts = atm_transmittance(A, transmittance_lut, rq, mu_s);
    vec3 S = irradiance * ((sr * pr + vec3(sm * pm)) * ts + (sr + vec3(sm)) * atm_multiple_scattering(A, ms_lut, rq, mu_s));
    vec3 step_t = exp(-ext * dt);
    L += T * S * (1.0 - step_t) / max(ext, vec3(1e-9));
    T *= step_t;
  }
  if (ground) {
    vec3 g = normalize(pos + dir * t_max);
    L += T * irradiance * atm_transmittance(A, transmittance_lut, A.radii.x, dot(g, light)) * max(dot(g, light), 0.0) *
         A.albedo.rgb / kAtmPi;
  }
  return L;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, ivec2(ATMOSPHERE_SKY_VIEW_W, ATMOSPHERE_SKY_VIEW_H)))) return;
  vec2 uv = (vec2(p) + 0.5) / vec2(ATMOSPHERE_SKY_VIEW_W, ATMOSPHERE_SKY_VIEW_H);
  // Values from the parameters alone, kept in variables: runtime_uniform.glsl says why they take a zero (here also
  // why a flying camera made lavapipe keep a compiled copy of this shader per altitude: `cumulo soak` measured it).
  float z = runtime_zero();
  vec3 sun = normalize(A.sun.xyz + z);
  vec3 dir = atm_sky_view_dir(uv, sun);
  float Rb = A.radii.x + z, Rt = A.radii.y + z;
  float r = clamp(Rb + max(A.view.x + z, 0.001), Rb, Rt - 0.001);
  bool ground = atm_hits_ground(r, dir.y, Rb);
  float t_max = ground ? atm_distance_to_ground(r, dir.y, Rb) : atm_distance_to_sphere(r, dir.y, Rt);
  vec3 L = scatter(dir, sun, A.albedo.w * A.sun.w + z, r, t_max, ground) +
           scatter(dir, normalize(A.moon.xyz + z), A.albedo.w * A.moon.w + z, r, t_max, ground) + A.ozone.w * vec3(1.0, 1.2, 2.0);
  imageStore(lut, p, vec4(L, 1.0));
}
