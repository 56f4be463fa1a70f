#version 450
// The march's inputs, step 3 (grown_attributes.cpp's derive_modeling, the distance): from each voxel's seed (the
// nearest voxel of the other class, sdf_jfa.comp), the distance between the two centres less half a voxel (the
// surface lies between them: volume/distance.h's signed_distance_from_mask), negative inside; next to the surface
// (a 6-neighbour of the other class, not on the grid's faces) the linear iso-crossing (iso - q) / |grad q| replaces
// it where smaller and of the same sign. No seed (no voxel of the other class): the field's far value.
// The result is the modeling's distance (the profile and its depth read it); sdf_store.comp makes it conservative.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Seeds { uint seeds[]; };
layout(set = 0, binding = 2, std430) readonly buffer Fine { float fine[]; };
layout(set = 0, binding = 3, std430) writeonly buffer Sdf { float sdf[]; };

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  ivec3 n = P.voxels.xyz;
  ivec3 v = grown_coords(id, n);
  uint s = seeds[id];
  bool inside = (s & GROWN_SEED_INSIDE) != 0u;
  float spacing = P.grid.y;
  float d;
  if ((s & GROWN_SEED_MASK) == GROWN_SEED_NONE) {
    d = P.field.y;
  } else {
    ivec3 o = grown_unpack(s & GROWN_SEED_MASK) - v;
    precise float e = sqrt(float(o.x * o.x + o.y * o.y + o.z * o.z)) * spacing - P.grid.w;
    d = e;
  }
  if (inside) d = -d;

  if (all(greaterThan(v, ivec3(0))) && all(lessThan(v, n - 1))) {
    int sy = n.x, sz = n.x * n.y;
    bool surface = false;
    for (int a = 0; a < 6; ++a) {
      int stride = (a >> 1) == 0 ? 1 : ((a >> 1) == 1 ? sy : sz);
      int q = (a & 1) == 0 ? id - stride : id + stride;
      surface = surface || ((seeds[q] & GROWN_SEED_INSIDE) != 0u) != inside;
    }
    if (surface) {
      vec3 grad = vec3(fine[id + 1] - fine[id - 1], fine[id + sy] - fine[id - sy], fine[id + sz] - fine[id - sz]);
      precise float len = length(grad) / (2.0 * spacing);
      if (len > 0.0) {
        precise float crossing = (P.grid.z - fine[id]) / len;
        if (abs(crossing) < abs(d) && (crossing > 0.0) == !inside) d = crossing;
      }
    }
  }
  sdf[id] = d;
}
