#version 450
// Cloud-formation solver, stage 5b (solver.cpp's add_forces, vorticity confinement; Fedkiw et al. 2001): the
// vorticity omega (1/s) at each cell centre by central differences (clamped at the walls) of the cell-centred
// velocity, which is computed here from the faces for each neighbour as the CPU computes it once per cell.
// Writes (omega, |omega|).
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, u)
GROW_FIELD(2, v)
GROW_FIELD(3, w)
GROW_VEC4S(4, omega)

vec3 cell_velocity(ivec3 c) {
  ivec3 n = P.dims.xyz;
  ivec3 du = n + ivec3(1, 0, 0), dv = n + ivec3(0, 1, 0), dw = n + ivec3(0, 0, 1);
  return 0.5 * vec3(u[grow_index(c, du)] + u[grow_index(c + ivec3(1, 0, 0), du)],
                    v[grow_index(c, dv)] + v[grow_index(c + ivec3(0, 1, 0), dv)],
                    w[grow_index(c, dw)] + w[grow_index(c + ivec3(0, 0, 1), dw)]);
}

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.dims.w) return;
  ivec3 n = P.dims.xyz, c = grow_coords(id, n), hi = n - 1;
  vec3 xp = cell_velocity(ivec3(min(c.x + 1, hi.x), c.y, c.z)), xm = cell_velocity(ivec3(max(c.x - 1, 0), c.y, c.z));
  vec3 yp = cell_velocity(ivec3(c.x, min(c.y + 1, hi.y), c.z)), ym = cell_velocity(ivec3(c.x, max(c.y - 1, 0), c.z));
  vec3 zp = cell_velocity(ivec3(c.x, c.y, min(c.z + 1, hi.z))), zm = cell_velocity(ivec3(c.x, c.y, max(c.z - 1, 0)));
  float inv2h = P.forces.w;
  vec3 o = vec3((yp.z - ym.z - (zp.y - zm.y)) * inv2h, (zp.x - zm.x - (xp.z - xm.z)) * inv2h,
                (xp.y - xm.y - (yp.x - ym.x)) * inv2h);
  omega[id] = vec4(o, length(o));
}
