#version 450
// Cloud-formation solver, stage 2d (solver.cpp's advect, scalars): MacCormack's corrector. The predictor traced
// forward again estimates the error, half of it is added back, and the result is clamped to the range of the
// nodes the backward trace sampled (stability). Writes new theta, qv and qc apart from the old ones, which
// neighbours still read.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_VEC4S(1, back)
GROW_VEC4S(2, fwd)
GROW_FIELD(3, theta)
GROW_FIELD(4, vapour)
GROW_FIELD(5, water)
GROW_FIELD(6, theta_hat)
GROW_FIELD(7, vapour_hat)
GROW_FIELD(8, water_hat)
GROW_FIELD(9, theta_out)
GROW_FIELD(10, vapour_out)
GROW_FIELD(11, water_out)

GROW_TRILINEAR(sample_theta_hat, theta_hat)
GROW_TRILINEAR(sample_vapour_hat, vapour_hat)
GROW_TRILINEAR(sample_water_hat, water_hat)
GROW_NODE_RANGE(range_theta, theta)
GROW_NODE_RANGE(range_vapour, vapour)
GROW_NODE_RANGE(range_water, water)

float corrected(float phi, float hat, float tilde, vec2 range) {
  return clamp(hat + 0.5 * (phi - tilde), range.x, range.y);
}

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  ivec3 n = P.dims.xyz;
  vec3 b = back[id].xyz, f = fwd[id].xyz;
  theta_out[id] = corrected(theta[id], theta_hat[id], sample_theta_hat(n, f), range_theta(n, b));
  vapour_out[id] = corrected(vapour[id], vapour_hat[id], sample_vapour_hat(n, f), range_vapour(n, b));
  water_out[id] = corrected(water[id], water_hat[id], sample_water_hat(n, f), range_water(n, b));
}
