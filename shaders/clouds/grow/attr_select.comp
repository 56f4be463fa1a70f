#version 450
// The march's inputs, the percentiles' radix select (attr_histogram.comp counted): per quantity, the 8-bit digit
// whose cumulative count passes the rank k joins the prefix, k becomes the rank within that digit, and the
// histogram is cleared for the next pass. The first pass also counts the cloud cells and sets the rank as
// grown_attributes.cpp's percentile does (k = min(n - 1, size_t(q * float(n - 1))), nth_element's k-th smallest).
// After four passes the prefix is the k-th value's bits, exactly.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_QUANTITIES) in;
layout(set = 0, binding = 1, std430) buffer Select { uint state[]; };

void main() {
  int q = int(gl_LocalInvocationID.x);
  int head = q * GROWN_SELECT_STRIDE, bins = GROWN_SELECT_HEADER + q * GROWN_BINS;
  int radix = grown_runtime(pc.pass.z);
  if (radix == 0) {
    uint count = 0u;
    for (int b = 0; b < GROWN_BINS; ++b) count += state[bins + b];
    state[head + GROWN_SELECT_COUNT] = count;
    state[head + GROWN_SELECT_RANK] = count > 0u ? min(count - 1u, uint(P.quantiles[q] * float(count - 1u))) : 0u;
    state[head + GROWN_SELECT_PREFIX] = 0u;
  }
  uint k = state[head + GROWN_SELECT_RANK], below = 0u;
  int digit = 0;
  for (int b = 0; b < GROWN_BINS; ++b) {
    uint h = state[bins + b];
    if (below + h > k) {
      digit = b;
      break;
    }
    below += h;
  }
  if (state[head + GROWN_SELECT_COUNT] > 0u) {
    state[head + GROWN_SELECT_RANK] = k - below;
    state[head + GROWN_SELECT_PREFIX] |= uint(digit) << uint(24 - 8 * radix);
  }
  for (int b = 0; b < GROWN_BINS; ++b) state[bins + b] = 0u;
}
