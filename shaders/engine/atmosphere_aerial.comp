#version 450
// Aerial-perspective froxels (Hillaire 2020 section 5.4): per screen cell (32x32), the camera ray's
// in-scattering of the sun and the moon (single scattering through the transmittance LUT, plus psi_ms,
// as the sky-view LUT) and its transmittance, accumulated slice by slice to 32 km (slice ends at
// (k + 1)^2 / 32^2 of it, atmosphere_params.h). The terrain (geometry_lit.frag) and the clouds' composite
// apply it at their distance: colour x transmittance + in-scattering.
#extension GL_GOOGLE_include_directive : require
#include "engine/atmosphere_common.glsl"
#include "engine/runtime_uniform.glsl"
#include "engine/view_ray.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ATMOSPHERE_PARAMS_BINDING, std140) uniform AtmosphereBlock { AtmosphereGpuParams A; };
layout(set = 0, binding = ATMOSPHERE_TRANSMITTANCE_BINDING) uniform sampler2D transmittance_lut;
layout(set = 0, binding = ATMOSPHERE_MS_BINDING) uniform sampler2D ms_lut;
layout(set = 0, binding = ATMOSPHERE_OUT_BINDING, rgba16f) uniform writeonly image3D aerial;
layout(push_constant) uniform Push { AtmosphereAerialPush pc; };

vec3 source(vec3 q, vec3 dir, vec3 light, float irradiance) {
  if (!(irradiance > 0.0)) return vec3(0.0);
  float rq = length(q), h = rq - A.radii.x, mu_s = dot(q, light) / rq;
  float nu = dot(dir, light);
  vec3 sr = atm_rayleigh_scattering(A, h);
  float sm = atm_mie_scattering(A, h);
  vec3 ts = atm_transmittance(A, transmittance_lut, rq, mu_s);
  return irradiance * ((sr * atm_rayleigh_phase(nu) + vec3(sm * atm_mie_phase(A.rayleigh.w, nu))) * ts +
                       (sr + vec3(sm)) * atm_multiple_scattering(A, ms_lut, rq, mu_s));
}

void main() {
  ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  const int N = ATMOSPHERE_AERIAL_SIZE;
  if (any(greaterThanEqual(cell, ivec2(N)))) return;
  vec2 uv = (vec2(cell) + 0.5) / float(N);
  vec3 dir = view_ray_dir(pc.inv_view_proj, uv * 2.0 - 1.0, pc.camera.xyz);
  // Values from the parameters alone, kept in variables: runtime_uniform.glsl says why they take a zero.
  float z = runtime_zero();
  float Rb = A.radii.x + z;
  vec3 pos = vec3(0.0, clamp(Rb + max(pc.camera.y * 0.001, 0.001), Rb, A.radii.y - 0.001), 0.0);
  vec3 sun = normalize(A.sun.xyz + z), moon = normalize(A.moon.xyz + z);
  float sun_e = A.albedo.w * A.sun.w + z, moon_e = A.albedo.w * A.moon.w + z;
  vec3 L = vec3(0.0), T = vec3(1.0);
  float t0 = 0.0;
  for (int k = 0; k < N; ++k) {
    float t_end = ATMOSPHERE_AERIAL_KM * float((k + 1) * (k + 1)) / float(N * N);
    // Two steps per slice (the far slices are 2 km long).
    for (int s = 0; s < 2; ++s) {
      float t1 = mix(t0, t_end, 0.5 * float(s + 1));
      float dt = t1 - (s == 0 ? t0 : mix(t0, t_end, 0.5));
      float t = t1 - 0.5 * dt;
      vec3 q = pos + dir * t;
      float hq = length(q) - Rb;
      vec3 ext = atm_extinction(A, hq);
      vec3 S = source(q, dir, sun, sun_e) + source(q, dir, moon, moon_e);
      vec3 step_t = exp(-ext * dt);
      L += T * S * (1.0 - step_t) / max(ext, vec3(1e-9));
      T *= step_t;
    }
    t0 = t_end;
    imageStore(aerial, ivec3(cell, k), vec4(L, dot(T, vec3(1.0 / 3.0))));
  }
}
