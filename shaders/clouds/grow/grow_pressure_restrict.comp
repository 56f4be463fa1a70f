#version 450
// Cloud-formation solver, pressure: restriction of a level's residual to the next coarser level's right-hand side
// (pressure.cpp: half the sum of the 8 children, in its order). One thread per coarse cell.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, fine_residual)
GROW_FIELD(2, coarse_b)
GROW_FIELD(3, state)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  int id = int(gl_GlobalInvocationID.x);
  if (id >= pc.coarse.w) return;
  ivec3 c = grow_coords(id, pc.coarse.xyz);
  float s = 0.0;
  for (int d = 0; d < 8; ++d)
    s += fine_residual[grow_index(2 * c + ivec3(d & 1, (d >> 1) & 1, d >> 2), pc.level.xyz)];
  coarse_b[id] = 0.5 * s;
}
