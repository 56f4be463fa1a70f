#version 450
// psi_ms LUT (Hillaire 2020 section 5.5, eq. 5-10): at (r, mu_s), the second-order light from 64
// directions (isotropic phase, unit irradiance, the ground lit with its albedo) times 1 / (1 - f_ms).
#extension GL_GOOGLE_include_directive : require
#include "engine/atmosphere_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ATMOSPHERE_PARAMS_BINDING, std140) uniform AtmosphereBlock { AtmosphereGpuParams A; };
layout(set = 0, binding = ATMOSPHERE_TRANSMITTANCE_BINDING) uniform sampler2D transmittance_lut;
layout(set = 0, binding = ATMOSPHERE_OUT_BINDING, rgba16f) uniform writeonly image2D lut;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, ivec2(ATMOSPHERE_MS_SIZE)))) return;
  float Rb = A.radii.x, Rt = A.radii.y;
  float r = Rb + (Rt - Rb) * (float(p.y) + 0.5) / float(ATMOSPHERE_MS_SIZE);
  float mu_s = -1.0 + 2.0 * (float(p.x) + 0.5) / float(ATMOSPHERE_MS_SIZE);
  vec3 pos = vec3(0.0, r, 0.0), sun = vec3(sqrt(max(0.0, 1.0 - mu_s * mu_s)), mu_s, 0.0);
  vec3 l2 = vec3(0.0), fms = vec3(0.0);
  const int kDirs = 8, kSteps = 20;
  for (int a = 0; a < kDirs; ++a)
    for (int b = 0; b < kDirs; ++b) {
      float cos_t = 1.0 - 2.0 * (float(a) + 0.5) / float(kDirs), phi = 2.0 * kAtmPi * (float(b) + 0.5) / float(kDirs);
      float sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
      vec3 d = vec3(sin_t * cos(phi), cos_t, sin_t * sin(phi));
      bool ground = atm_hits_ground(r, cos_t, Rb);
      float t_max = ground ? atm_distance_to_ground(r, cos_t, Rb) : atm_distance_to_sphere(r, cos_t, Rt);
      float dt = t_max / float(kSteps);
      vec3 T = vec3(1.0);
      for (int s = 0; s < kSteps; ++s) {
        vec3 q = pos + d * ((float(s) + 0.5) * dt);
        float rq = length(q), h = rq - Rb;
        vec3 sigma_s = atm_rayleigh_scattering(A, h) + vec3(atm_mie_scattering(A, h));
        vec3 ext = atm_extinction(A, h);
        vec3 step_t = exp(-ext * dt);
        vec3 integ = (1.0 - step_t) / max(ext, vec3(1e-9));
        vec3 ts = atm_transmittance(A, transmittance_lut, rq, dot(q, sun) / rq);
        l2 += T * sigma_s * ts * (1.0 / (4.0 * kAtmPi)) * integ;
        fms += T * sigma_s * integ;
        T *= step_t;
      }
      if (ground) {
        vec3 n = normalize(pos + d * t_max);
        l2 += T * atm_transmittance(A, transmittance_lut, Rb, dot(n, sun)) * max(dot(n, sun), 0.0) * A.albedo.rgb / kAtmPi;
      }
    }
  l2 /= float(kDirs * kDirs);
  fms /= float(kDirs * kDirs);
  imageStore(lut, p, vec4(l2 / (1.0 - min(fms, vec3(0.99))), 1.0));
}
