#version 450
// Cloud-formation solver, stage 2a (solver.cpp's advect, velocity): semi-Lagrangian advection of the three face
// velocities by the flow before the step (vorticity confinement restores what it smooths), then no flow through
// the walls. One thread per face of u, then of v, then of w.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, u_old)
GROW_FIELD(2, v_old)
GROW_FIELD(3, w_old)
GROW_FIELD(4, u_new)
GROW_FIELD(5, v_new)
GROW_FIELD(6, w_new)

#include "clouds/grow/grow_trace.glsl"

void main() {
  ivec3 n = P.dims.xyz;
  ivec3 du = n + ivec3(1, 0, 0), dv = n + ivec3(0, 1, 0), dw = n + ivec3(0, 0, 1);
  int nu = du.x * du.y * du.z, nv = dv.x * dv.y * dv.z, nw = dw.x * dw.y * dw.z;
  int id = int(gl_GlobalInvocationID.x);
  if (id < nu) {
    ivec3 c = grow_coords(id, du);
    vec3 offset = vec3(0.0, 0.5, 0.5);
    bool wall = c.x == 0 || c.x == n.x;
    u_new[id] = wall ? 0.0 : grow_sample_u(du, grow_trace(vec3(c) + offset, -1.0) - offset);
  } else if (id < nu + nv) {
    id -= nu;
    ivec3 c = grow_coords(id, dv);
    vec3 offset = vec3(0.5, 0.0, 0.5);
    bool wall = c.y == 0 || c.y == n.y;
    v_new[id] = wall ? 0.0 : grow_sample_v(dv, grow_trace(vec3(c) + offset, -1.0) - offset);
  } else if (id < nu + nv + nw) {
    id -= nu + nv;
    ivec3 c = grow_coords(id, dw);
    vec3 offset = vec3(0.5, 0.5, 0.0);
    bool wall = c.z == 0 || c.z == n.z;
    w_new[id] = wall ? 0.0 : grow_sample_w(dw, grow_trace(vec3(c) + offset, -1.0) - offset);
  }
}
