#version 450
// The march's inputs, the height within the cloud's column (grown_attributes.cpp): per column of cells (x, z), the
// lowest and highest cell above the iso (-1 without any).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Water { float water[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Columns { ivec2 columns[]; };

void main() {
  int id = int(gl_GlobalInvocationID.x);
  ivec3 n = P.cells.xyz;
  if (id >= n.x * n.z) return;
  int i = id % n.x, k = id / n.x;
  int lo = -1, hi = -1;
  int ny = grown_runtime(n.y);
  for (int j = 0; j < ny; ++j)
    if (water[i + n.x * (j + n.y * k)] > P.grid.z) {
      hi = j;
      lo = lo < 0 ? j : lo;
    }
  columns[id] = ivec2(lo, hi);
}
