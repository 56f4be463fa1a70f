#version 450
// Cloud-formation solver, stage 5a (solver.cpp's add_forces, buoyancy; Harris et al. 2003, eq. 7): the virtual
// temperature's excess with the drag of the condensed water, B = g ((theta' + 0.61 theta0 (qv - qv0)) / theta0 - qc),
// averaged onto the interior y faces. One thread per y face.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, theta)
GROW_FIELD(2, vapour)
GROW_FIELD(3, water)
GROW_VEC4S(4, ambient)  // per level: theta0, exner, pressure, qv0
GROW_FIELD(5, v)

float buoyancy(ivec3 c) {
  int x = grow_index(c, P.dims.xyz);
  float th0 = ambient[c.y].x, qv0 = ambient[c.y].w;
  return P.physics.w * ((theta[x] - th0 + 0.61 * th0 * (vapour[x] - qv0)) / th0 - water[x]);
}

void main() {
  ivec3 n = P.dims.xyz, dv = n + ivec3(0, 1, 0);
  int id = int(gl_GlobalInvocationID.x);
  if (id >= dv.x * dv.y * dv.z) return;
  ivec3 c = grow_coords(id, dv);
  if (c.y == 0 || c.y == n.y) return;
  v[id] += P.grid.y * 0.5 * (buoyancy(c - ivec3(0, 1, 0)) + buoyancy(c));
}
