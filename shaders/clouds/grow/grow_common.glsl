// Shared by the cloud-formation solver's shaders (shaders/clouds/grow, modules/clouds/grow_gpu): the parameter
// block, the push constants, cell indexing and the CPU solver's grid sampling (modules/clouds/bake/grow/solver.cpp:
// sample, node_range), written as macros because GLSL cannot pass a buffer to a function. Each expression keeps the
// CPU's order of operations, so that both round alike.
#ifndef CUMULO_GROW_COMMON_GLSL
#define CUMULO_GROW_COMMON_GLSL
#include "shared/grow_params.h"
#include "engine/runtime_uniform.glsl"

layout(set = 0, binding = GROW_BINDING_PARAMS, std140) uniform Params { GrowParams P; };
layout(push_constant) uniform Push { GrowPush pc; };

// A float field at binding b (std430, the CPU's index order).
#define GROW_FIELD(b, name) layout(set = 0, binding = b, std430) buffer name##_block { float name[]; };
#define GROW_VEC4S(b, name) layout(set = 0, binding = b, std430) buffer name##_block { vec4 name[]; };

// Loop bounds and branches that depend on the parameters alone go through runtime_uniform.glsl (lavapipe).
int grow_runtime(int v) { return int(runtime_uint(uint(v))); }

int grow_index(ivec3 c, ivec3 n) { return c.x + n.x * (c.y + n.y * c.z); }
ivec3 grow_coords(int id, ivec3 n) { return ivec3(id % n.x, (id / n.x) % n.y, id / (n.x * n.y)); }

// float name(ivec3 d, vec3 p): trilinear sample of the field of dims d at continuous index coordinates, clamped to
// the grid (solver.cpp's sample).
#define GROW_TRILINEAR(name, field)                                                                 \
  float name(ivec3 d, vec3 p) {                                                                     \
    p = clamp(p, vec3(0.0), vec3(d - 1));                                                           \
    ivec3 i0 = min(ivec3(p), max(d - 2, ivec3(0)));                                                 \
    ivec3 i1 = min(i0 + 1, d - 1);                                                                  \
    vec3 f = p - vec3(i0);                                                                          \
    int sy = d.x, sz = d.x * d.y;                                                                   \
    float a000 = field[i0.x + sy * i0.y + sz * i0.z], a100 = field[i1.x + sy * i0.y + sz * i0.z];   \
    float a010 = field[i0.x + sy * i1.y + sz * i0.z], a110 = field[i1.x + sy * i1.y + sz * i0.z];   \
    float a001 = field[i0.x + sy * i0.y + sz * i1.z], a101 = field[i1.x + sy * i0.y + sz * i1.z];   \
    float a011 = field[i0.x + sy * i1.y + sz * i1.z], a111 = field[i1.x + sy * i1.y + sz * i1.z];   \
    float c00 = a000 + (a100 - a000) * f.x;                                                         \
    float c10 = a010 + (a110 - a010) * f.x;                                                         \
    float c01 = a001 + (a101 - a001) * f.x;                                                         \
    float c11 = a011 + (a111 - a011) * f.x;                                                         \
    float c0 = c00 + (c10 - c00) * f.y, c1 = c01 + (c11 - c01) * f.y;                               \
    return c0 + (c1 - c0) * f.z;                                                                    \
  }

// vec2 name(ivec3 d, vec3 p): the range (min, max) of the 8 nodes around p, MacCormack's clamp (solver.cpp's
// node_range: no d - 2 limit there, so the upper node repeats at the far face).
#define GROW_NODE_RANGE(name, field)                                                                \
  vec2 name(ivec3 d, vec3 p) {                                                                      \
    p = clamp(p, vec3(0.0), vec3(d - 1));                                                           \
    ivec3 i0 = ivec3(p);                                                                            \
    ivec3 i1 = min(i0 + 1, d - 1);                                                                  \
    int sy = d.x, sz = d.x * d.y;                                                                   \
    float lo = 1e30, hi = -1e30;                                                                    \
    for (int c = 0; c < 8; ++c) {                                                                   \
      float v = field[((c & 1) != 0 ? i1.x : i0.x) + sy * ((c & 2) != 0 ? i1.y : i0.y) +            \
                      sz * ((c & 4) != 0 ? i1.z : i0.z)];                                           \
      lo = min(lo, v);                                                                              \
      hi = max(hi, v);                                                                              \
    }                                                                                               \
    return vec2(lo, hi);                                                                            \
  }

#endif
