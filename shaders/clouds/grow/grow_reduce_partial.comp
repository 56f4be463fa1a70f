#version 450
// Cloud-formation solver, pressure: the first pass of a sum over the grid. Each group adds GROW_REDUCE_BLOCK
// elements (4 per thread, then a tree in shared memory) into partials[group]: x = sum a b and y = sum a a
// (pc.control.w 0, dot products), or x = sum a (pc.control.w 1). A fixed order, no atomics: the same bytes every run.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_REDUCE_SIZE) in;
GROW_FIELD(1, a)
GROW_FIELD(2, b)
layout(set = 0, binding = 3, std430) buffer Partials { vec2 partials[]; };
GROW_FIELD(4, state)

shared vec2 sums[GROW_REDUCE_SIZE];

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;  // the same for every group
  int t = int(gl_LocalInvocationID.x);
  int base = int(gl_WorkGroupID.x) * GROW_REDUCE_BLOCK + t;
  bool sum_only = grow_runtime(pc.control.w) != 0;
  vec2 s = vec2(0.0);
  for (int e = 0; e < GROW_REDUCE_BLOCK / GROW_REDUCE_SIZE; ++e) {
    int c = base + e * GROW_REDUCE_SIZE;
    if (c >= pc.level.w) break;
    float va = a[c];
    if (sum_only) {
      s.x += va;
    } else {
      s.x += va * b[c];
      s.y += va * va;
    }
  }
  sums[t] = s;
  barrier();
  for (int stride = GROW_REDUCE_SIZE / 2; stride > 0; stride /= 2) {
    if (t < stride) sums[t] += sums[t + stride];
    barrier();
  }
  if (t == 0) partials[gl_WorkGroupID.x] = sums[0];
}
