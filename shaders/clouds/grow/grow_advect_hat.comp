#version 450
// Cloud-formation solver, stage 2c (solver.cpp's advect, scalars): MacCormack's predictor, each of theta, qv and qc
// sampled at the cell's backward trace.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_VEC4S(1, back)
GROW_FIELD(2, theta)
GROW_FIELD(3, vapour)
GROW_FIELD(4, water)
GROW_FIELD(5, theta_hat)
GROW_FIELD(6, vapour_hat)
GROW_FIELD(7, water_hat)

GROW_TRILINEAR(sample_theta, theta)
GROW_TRILINEAR(sample_vapour, vapour)
GROW_TRILINEAR(sample_water, water)

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  ivec3 n = P.dims.xyz;
  vec3 p = back[id].xyz;
  theta_hat[id] = sample_theta(n, p);
  vapour_hat[id] = sample_vapour(n, p);
  water_hat[id] = sample_water(n, p);
}
