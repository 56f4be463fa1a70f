#version 450
// Cloud-formation solver, stage 6c (solver.cpp's project): the pressure gradient subtracted from the interior
// faces (unit spacing), which leaves the flow divergence-free; the walls' faces are copied. Reads the forced
// velocities, writes the step's. One thread per face of u, then of v, then of w.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, u_in)
GROW_FIELD(2, v_in)
GROW_FIELD(3, w_in)
GROW_FIELD(4, pressure)
GROW_FIELD(5, u)
GROW_FIELD(6, v)
GROW_FIELD(7, w)

void main() {
  ivec3 n = P.dims.xyz;
  ivec3 du = n + ivec3(1, 0, 0), dv = n + ivec3(0, 1, 0), dw = n + ivec3(0, 0, 1);
  int nu = du.x * du.y * du.z, nv = dv.x * dv.y * dv.z, nw = dw.x * dw.y * dw.z;
  int id = int(gl_GlobalInvocationID.x);
  if (id < nu) {
    ivec3 c = grow_coords(id, du);
    int x = grow_index(c, n);
    u[id] = c.x == 0 || c.x == n.x ? u_in[id] : u_in[id] - (pressure[x] - pressure[x - 1]);
  } else if (id < nu + nv) {
    id -= nu;
    ivec3 c = grow_coords(id, dv);
    int x = grow_index(c, n);
    v[id] = c.y == 0 || c.y == n.y ? v_in[id] : v_in[id] - (pressure[x] - pressure[x - n.x]);
  } else if (id < nu + nv + nw) {
    id -= nu + nv;
    ivec3 c = grow_coords(id, dw);
    int x = grow_index(c, n);
    w[id] = c.z == 0 || c.z == n.z ? w_in[id] : w_in[id] - (pressure[x] - pressure[x - n.x * n.y]);
  }
}
