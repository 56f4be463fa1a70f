#version 450
// Cloud-formation solver, pressure: the multigrid's coarsest level (pressure.cpp's vcycle at the last level): 24
// red-black sweeps, then 24 black-red ones (symmetric, so the V-cycle stays a valid CG preconditioner), from x = 0.
// The level is small (a few dozen to a few thousand cells): one work group does all 96 half sweeps, with a
// barrier between them, instead of 96 dispatches.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"
#include "clouds/grow/grow_pressure_common.glsl"

layout(local_size_x = GROW_REDUCE_SIZE) in;
GROW_FIELD(1, x)
GROW_FIELD(2, b)
GROW_FIELD(3, state)

GROW_NEIGHBOURS(neighbours, x)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;  // the same for the whole group: the barriers below stay uniform
  ivec3 n = pc.level.xyz;
  int cells = grow_runtime(pc.level.w);
  int t = int(gl_LocalInvocationID.x);
  for (int c = t; c < cells; c += GROW_REDUCE_SIZE) x[c] = 0.0;
  memoryBarrierBuffer();
  barrier();
  for (int h = 0; h < 96; ++h) {
    int colour = h < 48 ? (h & 1) : 1 - (h & 1);
    for (int c = t; c < cells; c += GROW_REDUCE_SIZE) {
      ivec3 p = grow_coords(c, n);
      if (((p.x + p.y + p.z) & 1) != colour) continue;
      int m;
      float s = neighbours(n, p, c, m);
      x[c] = (b[c] + s) / float(max(m, 1));
    }
    memoryBarrierBuffer();
    barrier();
  }
}
