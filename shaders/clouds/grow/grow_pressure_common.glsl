// The cloud solver's pressure solve on the GPU (modules/clouds/grow_gpu/gpu_pressure.h; the CPU's is
// modules/clouds/bake/grow/pressure.cpp): the cell-centred 7-point Poisson operator with free-slip (Neumann) walls,
// A = -Laplacian in unit spacing on a multigrid level of dims pc.level.xyz. Every pass of the solve's loop first reads
// the shared state's `done`: once the conjugate gradients stopped, the rest of the recorded iterations do nothing.
#ifndef CUMULO_GROW_PRESSURE_COMMON_GLSL
#define CUMULO_GROW_PRESSURE_COMMON_GLSL

// float name(ivec3 n, ivec3 c, int cell, out int m): the sum of the in-box neighbours of cell c (index `cell`) and
// their count, in pressure.cpp's order (-x, +x, -y, +y, -z, +z), which its rounding depends on.
#define GROW_NEIGHBOURS(name, field)                                                                \
  float name(ivec3 n, ivec3 c, int cell, out int m) {                                               \
    float s = 0.0;                                                                                  \
    m = 0;                                                                                          \
    int sy = n.x, sz = n.x * n.y;                                                                   \
    if (c.x > 0) { s += field[cell - 1]; ++m; }                                                     \
    if (c.x < n.x - 1) { s += field[cell + 1]; ++m; }                                               \
    if (c.y > 0) { s += field[cell - sy]; ++m; }                                                    \
    if (c.y < n.y - 1) { s += field[cell + sy]; ++m; }                                              \
    if (c.z > 0) { s += field[cell - sz]; ++m; }                                                    \
    if (c.z < n.z - 1) { s += field[cell + sz]; ++m; }                                              \
    return s;                                                                                       \
  }

int grow_neighbour_count(ivec3 n, ivec3 c) {
  return int(c.x > 0) + int(c.x < n.x - 1) + int(c.y > 0) + int(c.y < n.y - 1) + int(c.z > 0) + int(c.z < n.z - 1);
}

#endif
