#version 450
// The march's inputs, one ring of grown_attributes.cpp's dilate: a cell outside the cloud whose 6-neighbours include
// known cells takes their mean (summed in the CPU's order: -x, +x, -y, +y, -z, +z) and becomes known, so that the
// output's trilinear samples at the surface do not blend in meaningless values.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer In { vec4 attributes_in[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Out { vec4 attributes_out[]; };

void main() {
  int c = int(gl_GlobalInvocationID.x);
  if (c >= P.cells.w) return;
  vec4 a = attributes_in[c];
  if (a.z != 0.0) {
    attributes_out[c] = a;
    return;
  }
  ivec3 n = P.cells.xyz;
  ivec3 cell = grown_coords(c, n);
  precise vec2 s = vec2(0.0);
  int m = 0;
  for (int k = 0; k < 6; ++k) {
    ivec3 p = cell;
    p[k >> 1] += (k & 1) == 0 ? -1 : 1;
    if (!grown_inside_grid(p, n)) continue;
    vec4 b = attributes_in[grown_index(p, n)];
    if (b.z != 0.0) {
      s += b.xy;
      ++m;
    }
  }
  attributes_out[c] = m > 0 ? vec4(s / float(m), 1.0, 0.0) : a;
}
