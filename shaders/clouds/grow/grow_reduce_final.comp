#version 450
// Cloud-formation solver, pressure: the second pass of a sum (one group folds pc.control.z partial sums in a fixed
// order), then the conjugate gradients' scalar step on it (pressure.cpp's solve; pc.control.y, GROW_OP_*). The CPU
// adds in doubles, this in floats: the iterates differ by rounding, the converged pressure does not. When the solve
// stops, its pc.solve.x indirect dispatches are emptied (their group counts zeroed, this pass's own included).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_REDUCE_SIZE) in;
layout(set = 0, binding = 1, std430) buffer Partials { vec2 partials[]; };
GROW_FIELD(2, state)
layout(set = 0, binding = 3, std430) buffer Dispatches { uint dispatches[]; };  // VkDispatchIndirectCommand each

shared vec2 sums[GROW_REDUCE_SIZE];

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  int t = int(gl_LocalInvocationID.x);
  int count = grow_runtime(pc.control.z);
  vec2 s = vec2(0.0);
  for (int g = t; g < count; g += GROW_REDUCE_SIZE) s += partials[g];
  sums[t] = s;
  barrier();
  for (int stride = GROW_REDUCE_SIZE / 2; stride > 0; stride /= 2) {
    if (t < stride) sums[t] += sums[t + stride];
    barrier();
  }
  if (t != 0) return;
  s = sums[0];
  float tolerance = P.pressure.x * state[GROW_STATE_BNORM];
  int op = grow_runtime(pc.control.y);
  if (op == GROW_OP_MEAN) {
    state[GROW_STATE_MEAN] = s.x / float(pc.level.w);
  } else if (op == GROW_OP_BNORM) {
    float bnorm = sqrt(s.x);
    state[GROW_STATE_BNORM] = bnorm;
    if (!(bnorm > 0.0)) state[GROW_STATE_DONE] = 2.0;
  } else if (op == GROW_OP_RZ_INIT) {
    state[GROW_STATE_RZ] = s.x;
    if (sqrt(s.y) <= tolerance) state[GROW_STATE_DONE] = 1.0;
  } else if (op == GROW_OP_PQ) {
    if (!(s.x > 0.0)) {
      state[GROW_STATE_DONE] = 1.0;
    } else {
      state[GROW_STATE_ALPHA] = state[GROW_STATE_RZ] / s.x;
      state[GROW_STATE_ITERATIONS] += 1.0;
    }
  } else if (op == GROW_OP_RZ_NEXT) {
    state[GROW_STATE_BETA] = s.x / state[GROW_STATE_RZ];
    state[GROW_STATE_RZ] = s.x;
    if (sqrt(s.y) <= tolerance) state[GROW_STATE_DONE] = 1.0;
  }
  if (state[GROW_STATE_DONE] != 0.0) {
    int entries = grow_runtime(pc.solve.x);
    for (int e = 0; e < entries; ++e) dispatches[3 * e] = 0u;
  }
}
