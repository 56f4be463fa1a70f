#version 450
// Cloud-formation solver, pressure: the conjugate gradients' vector updates (pressure.cpp's solve), while the solve
// iterates. UPDATE 0: x += alpha p, r -= alpha q. UPDATE 1: p = z + beta p. UPDATE 2: x = 0 after a zero right-hand
// side (the CPU's early return), else nothing.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

#ifndef UPDATE
#define UPDATE 0
#endif

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, state)
#if UPDATE == 0
GROW_FIELD(2, x)
GROW_FIELD(3, r)
GROW_FIELD(4, p)
GROW_FIELD(5, q)
#elif UPDATE == 1
GROW_FIELD(2, p)
GROW_FIELD(3, z)
#else
GROW_FIELD(2, x)
#endif

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= pc.level.w) return;
#if UPDATE == 2
  if (state[GROW_STATE_DONE] == 2.0) x[id] = 0.0;
#else
  if (state[GROW_STATE_DONE] != 0.0) return;
#if UPDATE == 0
  float alpha = state[GROW_STATE_ALPHA];
  x[id] += alpha * p[id];
  r[id] -= alpha * q[id];
#else
  p[id] = z[id] + state[GROW_STATE_BETA] * p[id];
#endif
#endif
}
