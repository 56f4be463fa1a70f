#version 450
// Cloud-formation solver, pressure: a field minus the mean grow_reduce_final.comp found (pressure.cpp's
// remove_mean: constants are the Neumann problem's null space).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, a)
GROW_FIELD(2, state)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  int id = int(gl_GlobalInvocationID.x);
  if (id >= pc.level.w) return;
  a[id] -= state[GROW_STATE_MEAN];
}
