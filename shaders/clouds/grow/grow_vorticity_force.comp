#version 450
// Cloud-formation solver, stage 5c (solver.cpp's add_forces): the confinement force eps (N x omega) at each cell
// centre, N the unit gradient of |omega| (central differences, clamped at the walls); eps = vorticity x 10 m/s
// (solver.cpp says why).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_VEC4S(1, omega)
GROW_VEC4S(2, force)

float magnitude(ivec3 c) { return omega[grow_index(c, P.dims.xyz)].w; }

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  ivec3 n = P.dims.xyz, c = grow_coords(id, n), hi = n - 1;
  vec3 g = vec3(magnitude(ivec3(min(c.x + 1, hi.x), c.y, c.z)) - magnitude(ivec3(max(c.x - 1, 0), c.y, c.z)),
                magnitude(ivec3(c.x, min(c.y + 1, hi.y), c.z)) - magnitude(ivec3(c.x, max(c.y - 1, 0), c.z)),
                magnitude(ivec3(c.x, c.y, min(c.z + 1, hi.z))) - magnitude(ivec3(c.x, c.y, max(c.z - 1, 0))));
  float len = length(g);
  force[id] = vec4(len > 1e-12 ? P.forces.z * cross(g / len, omega[id].xyz) : vec3(0.0), 0.0);
}
