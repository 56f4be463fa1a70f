#version 450
// The march's inputs, the detail type and density scale per solver cell (grown_attributes.cpp's derive_modeling):
//   type = 0.5 + 0.5 ((1 - height weight) rates + height weight (2 h - 1)), clamped to 0..1,
//   rates = growth weight growth / its 90th percentile + condensation weight condensation / its 90th percentile
//           + updraft weight w / its 90th percentile, h the height within the cloud's column (0 base, 1 top);
//   density = (0.45 + 0.55 thin) (1 - 0.3 evaporating), thin = cloud water / its median, evaporating = -condensation
//           / its 90th percentile (both clamped to 0..1).
// Each cell also says whether it is cloud (above the iso): the others take their values from attr_dilate.comp.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Water { float water[]; };
layout(set = 0, binding = 2, std430) readonly buffer Condensation { float condensation[]; };
layout(set = 0, binding = 3, std430) readonly buffer Growth { float growth[]; };
layout(set = 0, binding = 4, std430) readonly buffer VelocityV { float velocity_v[]; };
layout(set = 0, binding = 5, std430) readonly buffer Select { uint state[]; };
layout(set = 0, binding = 6, std430) readonly buffer Columns { ivec2 columns[]; };
layout(set = 0, binding = 7, std430) writeonly buffer Attributes { vec4 attributes[]; };  // type, density, known, 0

// The percentile of quantity k (0 without cloud cells), at least its floor.
float reference(int k) {
  int head = k * GROWN_SELECT_STRIDE;
  float v = state[head + GROWN_SELECT_COUNT] > 0u ? uintBitsToFloat(state[head + GROWN_SELECT_PREFIX]) : 0.0;
  return max(v, P.floors[k]);
}

void main() {
  int c = int(gl_GlobalInvocationID.x);
  if (c >= P.cells.w) return;
  ivec3 n = P.cells.xyz;
  ivec3 cell = grown_coords(c, n);
  int iv = cell.x + n.x * (cell.y + (n.y + 1) * cell.z);
  float w = 0.5 * (velocity_v[iv] + velocity_v[iv + n.x]);
  float qc = water[c];
  precise float cn = condensation[c] / reference(0);
  precise float wn = w / reference(1);
  precise float gn = growth[c] / reference(2);
  precise float rates = P.detail.x * gn + P.detail.y * cn + P.detail.z * wn;
  ivec2 column = columns[cell.x + n.x * cell.z];
  float h = 0.5;
  if (column.x >= 0 && cell.y >= column.x && cell.y <= column.y && column.y > column.x)
    h = float(cell.y - column.x) / float(column.y - column.x);
  precise float type = 0.5 + 0.5 * ((1.0 - P.detail.w) * rates + P.detail.w * (2.0 * h - 1.0));
  float thin = clamp(qc / reference(3), 0.0, 1.0);
  float evaporating = clamp(-cn, 0.0, 1.0);
  precise float density = (0.45 + 0.55 * thin) * (1.0 - 0.3 * evaporating);
  attributes[c] = vec4(clamp(type, 0.0, 1.0), density, qc > P.grid.z ? 1.0 : 0.0, 0.0);
}
