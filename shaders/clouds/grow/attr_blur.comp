#version 450
// The march's inputs, grown_attributes.cpp's blur3 along one axis (pc.pass.y) of the detail type: 1/4, 1/2, 1/4,
// the cell itself beyond the grid. The density scale passes through. Cells the dilation did not reach take 0.5
// (its fallback) for both.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer In { vec4 attributes_in[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Out { vec4 attributes_out[]; };

vec4 known(vec4 a) { return a.z != 0.0 ? a : vec4(0.5, 0.5, 1.0, 0.0); }

void main() {
  int c = int(gl_GlobalInvocationID.x);
  if (c >= P.cells.w) return;
  ivec3 n = P.cells.xyz;
  ivec3 cell = grown_coords(c, n);
  int axis = grown_runtime(pc.pass.y);
  int stride = axis == 0 ? 1 : (axis == 1 ? n.x : n.x * n.y);
  vec4 mid = known(attributes_in[c]);
  float lo = cell[axis] > 0 ? known(attributes_in[c - stride]).x : mid.x;
  float hi = cell[axis] + 1 < n[axis] ? known(attributes_in[c + stride]).x : mid.x;
  precise float type = 0.25 * lo + 0.5 * mid.x + 0.25 * hi;
  attributes_out[c] = vec4(type, mid.y, 1.0, 0.0);
}
