#version 450
// Transmittance LUT (Hillaire 2020 section 4; Bruneton's parameterization, atmosphere_common.glsl): per
// texel (r, mu), exp(-optical depth) to the top of the atmosphere, 40 steps.
#extension GL_GOOGLE_include_directive : require
#include "engine/atmosphere_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ATMOSPHERE_PARAMS_BINDING, std140) uniform AtmosphereBlock { AtmosphereGpuParams A; };
layout(set = 0, binding = ATMOSPHERE_OUT_BINDING, rgba16f) uniform writeonly image2D lut;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, ivec2(ATMOSPHERE_TRANSMITTANCE_W, ATMOSPHERE_TRANSMITTANCE_H)))) return;
  float r, mu;
  atm_transmittance_r_mu(A, vec2(p) + 0.5, r, mu);
  float t_max = max(atm_distance_to_sphere(r, mu, A.radii.y), 0.0);
  const int kSteps = 40;
  float dt = t_max / float(kSteps);
  vec3 od = vec3(0.0);
  for (int s = 0; s < kSteps; ++s) {
    float t = (float(s) + 0.5) * dt;
    float rq = sqrt(r * r + t * t + 2.0 * r * mu * t);
    od += atm_extinction(A, rq - A.radii.x) * dt;
  }
  imageStore(lut, p, vec4(exp(-od), 1.0));
}
