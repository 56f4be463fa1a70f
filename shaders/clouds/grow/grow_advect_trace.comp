#version 450
// Cloud-formation solver, stage 2b (solver.cpp's advect, scalars): MacCormack's one backward and one forward trace
// per cell, shared by theta, qv and qc (index coordinates: cell centres at integers).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, u_old)
GROW_FIELD(2, v_old)
GROW_FIELD(3, w_old)
GROW_VEC4S(4, back)
GROW_VEC4S(5, fwd)

#include "clouds/grow/grow_trace.glsl"

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  vec3 half_cell = vec3(0.5);
  vec3 p = vec3(grow_coords(id, P.dims.xyz)) + half_cell;
  back[id] = vec4(grow_trace(p, -1.0) - half_cell, 0.0);
  fwd[id] = vec4(grow_trace(p, 1.0) - half_cell, 0.0);
}
