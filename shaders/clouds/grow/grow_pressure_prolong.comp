#version 450
// Cloud-formation solver, pressure: piecewise-constant prolongation (pressure.cpp: the transpose of the
// restriction), the coarse correction added to each fine cell. One thread per fine cell.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, coarse_x)
GROW_FIELD(2, fine_x)
GROW_FIELD(3, state)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  int id = int(gl_GlobalInvocationID.x);
  if (id >= pc.level.w) return;
  ivec3 c = grow_coords(id, pc.level.xyz);
  fine_x[id] += coarse_x[grow_index(c / 2, pc.coarse.xyz)];
}
