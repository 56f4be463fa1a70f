#version 450
// Cloud-formation solver, pressure: out = A x (RESIDUAL 0: the conjugate gradients' q = A p) or out = b - A x
// (RESIDUAL 1: the solve's first residual and each multigrid level's), on the level pc.level (pressure.cpp's apply).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"
#include "clouds/grow/grow_pressure_common.glsl"

#ifndef RESIDUAL
#define RESIDUAL 1
#endif

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, x)
GROW_FIELD(2, b)
GROW_FIELD(3, result)
GROW_FIELD(4, state)

GROW_NEIGHBOURS(neighbours, x)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  int id = int(gl_GlobalInvocationID.x);
  if (id >= pc.level.w) return;
  ivec3 n = pc.level.xyz, c = grow_coords(id, n);
  int m;
  float s = neighbours(n, c, id, m);
  float ax = float(m) * x[id] - s;
#if RESIDUAL
  result[id] = b[id] - ax;
#else
  result[id] = ax;
#endif
}
