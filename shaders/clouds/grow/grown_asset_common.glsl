// Shared by the passes that turn the solver's state into the march's inputs (sdf_*.comp, attr_*.comp;
// modules/clouds/grow_gpu/grown_asset_gpu.h): the parameter block, the push constants, indexing on both grids and
// grown_attributes.cpp's trilinear sample (glm::mix's x (1 - a) + y a, in its order), as a macro because GLSL cannot
// pass a buffer to a function. `precise` keeps the compiler from fusing what the CPU rounds twice.
#ifndef CUMULO_GROWN_ASSET_COMMON_GLSL
#define CUMULO_GROWN_ASSET_COMMON_GLSL
#include "shared/grown_asset_params.h"
#include "engine/runtime_uniform.glsl"

layout(set = 0, binding = GROWN_BINDING_PARAMS, std140) uniform Params { GrownAssetParams P; };
layout(push_constant) uniform Push { GrownAssetPush pc; };

// Loop bounds and branches that depend on the parameters alone go through runtime_uniform.glsl (lavapipe).
int grown_runtime(int v) { return int(runtime_uint(uint(v))); }

int grown_index(ivec3 c, ivec3 n) { return c.x + n.x * (c.y + n.y * c.z); }
ivec3 grown_coords(int id, ivec3 n) { return ivec3(id % n.x, (id / n.x) % n.y, id / (n.x * n.y)); }
bool grown_inside_grid(ivec3 c, ivec3 n) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, n)); }

uint grown_pack(ivec3 c) { return uint(c.x) | (uint(c.y) << 10) | (uint(c.z) << 20); }
ivec3 grown_unpack(uint s) { return ivec3(int(s & 1023u), int((s >> 10) & 1023u), int((s >> 20) & 1023u)); }

// The output voxel's position in cell index coordinates (grown_attributes.cpp: glm::vec3(x, y, z) / float(f)).
vec3 grown_cell_position(ivec3 v) { return vec3(v) / P.grid.x; }

float grown_mix(float x, float y, float a) {
  precise float r = x * (1.0 - a) + y * a;
  return r;
}

// float name(ivec3 d, vec3 p): grown_attributes.cpp's trilinear over the field of dims d (clamped to the grid).
// `field` is read as field[index] SWIZZLE (empty for a float buffer, .x for a vec4 one).
#define GROWN_TRILINEAR(name, field, SWIZZLE)                                                                \
  float name(ivec3 d, vec3 p) {                                                                              \
    p = clamp(p, vec3(0.0), vec3(d) - 1.0);                                                                  \
    ivec3 a = min(ivec3(p), max(d, ivec3(2)) - 2);                                                           \
    ivec3 b = min(a + 1, d - 1);                                                                             \
    vec3 f = p - vec3(a);                                                                                    \
    int sy = d.x, sz = d.x * d.y;                                                                            \
    float c00 = grown_mix(field[a.x + sy * a.y + sz * a.z] SWIZZLE, field[b.x + sy * a.y + sz * a.z] SWIZZLE, f.x); \
    float c10 = grown_mix(field[a.x + sy * b.y + sz * a.z] SWIZZLE, field[b.x + sy * b.y + sz * a.z] SWIZZLE, f.x); \
    float c01 = grown_mix(field[a.x + sy * a.y + sz * b.z] SWIZZLE, field[b.x + sy * a.y + sz * b.z] SWIZZLE, f.x); \
    float c11 = grown_mix(field[a.x + sy * b.y + sz * b.z] SWIZZLE, field[b.x + sy * b.y + sz * b.z] SWIZZLE, f.x); \
    return grown_mix(grown_mix(c00, c10, f.y), grown_mix(c01, c11, f.y), f.z);                               \
  }

#endif
