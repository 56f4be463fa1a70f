#version 450
// Cloud-formation solver, pressure: one red-black Gauss-Seidel half sweep on a multigrid level (pressure.cpp's
// smooth): the cells of colour pc.control.x ((x + y + z) & 1) take the value that zeroes their residual. They read
// only the other colour, so the half sweep has no order. One thread per cell of the colour.
// FROM_ZERO 1: the first red half sweep of a V-cycle level, from x = 0 (the CPU clears x first): red cells take
// b / m (their neighbours are all 0), black ones 0; nothing is read of x. One thread per cell.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grow_common.glsl"
#include "clouds/grow/grow_pressure_common.glsl"

#ifndef FROM_ZERO
#define FROM_ZERO 0
#endif

layout(local_size_x = GROW_LOCAL_SIZE) in;
GROW_FIELD(1, x)
GROW_FIELD(2, b)
GROW_FIELD(3, state)

GROW_NEIGHBOURS(neighbours, x)

void main() {
  if (state[GROW_STATE_DONE] != 0.0) return;
  ivec3 n = pc.level.xyz;
  int id = int(gl_GlobalInvocationID.x);
#if FROM_ZERO
  if (id >= pc.level.w) return;
  ivec3 c = grow_coords(id, n);
  if (((c.x + c.y + c.z) & 1) != 0) {
    x[id] = 0.0;
    return;
  }
  x[id] = b[id] / float(max(grow_neighbour_count(n, c), 1));
#else
  int half_x = (n.x + 1) / 2;
  if (id >= half_x * n.y * n.z) return;
  int j = (id / half_x) % n.y, k = id / (half_x * n.y);
  ivec3 c = ivec3(2 * (id % half_x) + ((j + k + grow_runtime(pc.control.x)) & 1), j, k);
  if (c.x >= n.x) return;
  int cell = grow_index(c, n), m;
  float s = neighbours(n, c, cell, m);
  x[cell] = (b[cell] + s) / float(max(m, 1));
#endif
}
