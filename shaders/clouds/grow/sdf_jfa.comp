#version 450
// The march's inputs, step 2: one pass of jump flooding (Rong & Tan 2006, "Jump flooding in GPU with applications
// to Voronoi diagram and distance transform": log2 N passes of halving steps, then extra passes of steps 4, 2 and 1,
// one more than their "JFA+2", which kept farther seeds far from the cloud on a test grid).
// Every voxel keeps the nearest voxel of the OTHER class it has seen: a neighbour at +-step (27 of them, itself
// included) offers itself when its class differs, else its own seed. That is two independent floods in one buffer
// (the nearest inside voxel for outside voxels, the nearest outside voxel for inside ones), since a voxel only ever
// reads the other flood through voxels of its own class. Squared distances are integers and the 27 offers are
// taken in a fixed order (the first of equals wins): the same bytes every run.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer SeedsIn { uint seeds_in[]; };
layout(set = 0, binding = 2, std430) writeonly buffer SeedsOut { uint seeds_out[]; };

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  ivec3 n = P.voxels.xyz;
  ivec3 v = grown_coords(id, n);
  uint inside = seeds_in[id] & GROWN_SEED_INSIDE;
  int step = grown_runtime(pc.pass.x);
  uint best = GROWN_SEED_NONE;
  int best_d2 = 0x7FFFFFFF;
  for (int o = 0; o < 27; ++o) {
    // Offers from beyond the grid come from its nearest voxel instead (a real voxel: a valid, if repeated, offer).
    ivec3 p = clamp(v + step * (ivec3(o % 3, (o / 3) % 3, o / 9) - 1), ivec3(0), n - 1);
    uint s = seeds_in[grown_index(p, n)];
    uint offer = (s & GROWN_SEED_INSIDE) != inside ? grown_pack(p) : (s & GROWN_SEED_MASK);
    if (offer == GROWN_SEED_NONE) continue;
    ivec3 d = grown_unpack(offer) - v;
    int d2 = d.x * d.x + d.y * d.y + d.z * d.z;
    if (d2 < best_d2) {
      best_d2 = d2;
      best = offer;
    }
  }
  seeds_out[id] = inside | best;
}
