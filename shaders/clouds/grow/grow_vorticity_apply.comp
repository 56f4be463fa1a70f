#version 450
// Cloud-formation solver, stage 5d (solver.cpp's add_forces): the cell-centred confinement force times dt,
// averaged onto the interior faces. One thread per face of u, then of v, then of w.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_VEC4S(1, force)
GROW_FIELD(2, u)
GROW_FIELD(3, v)
GROW_FIELD(4, w)

void main() {
  ivec3 n = P.dims.xyz;
  ivec3 du = n + ivec3(1, 0, 0), dv = n + ivec3(0, 1, 0), dw = n + ivec3(0, 0, 1);
  int nu = du.x * du.y * du.z, nv = dv.x * dv.y * dv.z, nw = dw.x * dw.y * dw.z;
  float dt = P.grid.y;
  int id = int(gl_GlobalInvocationID.x);
  if (id < nu) {
    ivec3 c = grow_coords(id, du);
    if (c.x == 0 || c.x == n.x) return;
    int x = grow_index(c, n);
    u[id] += 0.5 * (force[x].x * dt + force[x - 1].x * dt);
  } else if (id < nu + nv) {
    id -= nu;
    ivec3 c = grow_coords(id, dv);
    if (c.y == 0 || c.y == n.y) return;
    int x = grow_index(c, n);
    v[id] += 0.5 * (force[x].y * dt + force[x - n.x].y * dt);
  } else if (id < nu + nv + nw) {
    id -= nu + nv;
    ivec3 c = grow_coords(id, dw);
    if (c.z == 0 || c.z == n.z) return;
    int x = grow_index(c, n);
    w[id] += 0.5 * (force[x].z * dt + force[x - n.x * n.y].z * dt);
  }
}
