#version 450
// Cloud-formation solver, stage 6a (solver.cpp's project): the pressure solve's right-hand side, minus the
// divergence of the face velocities (unit spacing, as the CPU's).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, u)
GROW_FIELD(2, v)
GROW_FIELD(3, w)
GROW_FIELD(4, rhs)

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  ivec3 n = P.dims.xyz, c = grow_coords(id, n);
  ivec3 du = n + ivec3(1, 0, 0), dv = n + ivec3(0, 1, 0), dw = n + ivec3(0, 0, 1);
  float div = u[grow_index(c + ivec3(1, 0, 0), du)] - u[grow_index(c, du)] + v[grow_index(c + ivec3(0, 1, 0), dv)] -
              v[grow_index(c, dv)] + w[grow_index(c + ivec3(0, 0, 1), dw)] - w[grow_index(c, dw)];
  rhs[id] = -div;
}
