#version 450
// The march's inputs, the attributes' percentiles (grown_attributes.cpp: the 90th percentile of |condensation|,
// |w| and |growth| and the median of the cloud water, over the cells above the iso), exactly: a radix select on
// the values' float bits (non-negative floats order as their bits do), 8 bits a pass from the top. This pass counts
// the cloud cells whose bits agree with the prefix found so far, one histogram of the next 8 bits per quantity:
// a group counts GROWN_HISTOGRAM_CELLS cells in shared memory, then adds its non-zero bins to the global ones.
// Integer atomics only: the counts, and so the selected values, are the same every run.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_HISTOGRAM_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Water { float water[]; };
layout(set = 0, binding = 2, std430) readonly buffer Condensation { float condensation[]; };
layout(set = 0, binding = 3, std430) readonly buffer Growth { float growth[]; };
layout(set = 0, binding = 4, std430) readonly buffer VelocityV { float velocity_v[]; };
layout(set = 0, binding = 5, std430) buffer Select { uint state[]; };

shared uint bins[GROWN_QUANTITIES * GROWN_BINS];

void main() {
  int t = int(gl_LocalInvocationID.x);
  for (int i = t; i < GROWN_QUANTITIES * GROWN_BINS; i += GROWN_HISTOGRAM_SIZE) bins[i] = 0u;
  barrier();
  int radix = grown_runtime(pc.pass.z);
  int shift = 24 - 8 * radix;
  uint mask = radix == 0 ? 0u : (0xFFFFFFFFu << uint(32 - 8 * radix));
  uvec4 prefix = uvec4(state[0 * GROWN_SELECT_STRIDE + GROWN_SELECT_PREFIX], state[1 * GROWN_SELECT_STRIDE + GROWN_SELECT_PREFIX],
                       state[2 * GROWN_SELECT_STRIDE + GROWN_SELECT_PREFIX], state[3 * GROWN_SELECT_STRIDE + GROWN_SELECT_PREFIX]);
  ivec3 n = P.cells.xyz;
  int base = int(gl_WorkGroupID.x) * GROWN_HISTOGRAM_CELLS + t;
  for (int e = 0; e < GROWN_HISTOGRAM_CELLS / GROWN_HISTOGRAM_SIZE; ++e) {
    int c = base + e * GROWN_HISTOGRAM_SIZE;
    if (c >= P.cells.w) break;
    float q = water[c];
    if (!(q > P.grid.z)) continue;
    ivec3 cell = grown_coords(c, n);
    int iv = cell.x + n.x * (cell.y + (n.y + 1) * cell.z);
    float w = 0.5 * (velocity_v[iv] + velocity_v[iv + n.x]);  // solver.cpp's vertical_velocity
    uvec4 key = floatBitsToUint(vec4(abs(condensation[c]), abs(w), abs(growth[c]), q));
    for (int k = 0; k < GROWN_QUANTITIES; ++k)
      if ((key[k] & mask) == (prefix[k] & mask)) atomicAdd(bins[k * GROWN_BINS + int((key[k] >> uint(shift)) & 255u)], 1u);
  }
  barrier();
  for (int i = t; i < GROWN_QUANTITIES * GROWN_BINS; i += GROWN_HISTOGRAM_SIZE)
    if (bins[i] != 0u) atomicAdd(state[GROWN_SELECT_HEADER + i], bins[i]);
}
