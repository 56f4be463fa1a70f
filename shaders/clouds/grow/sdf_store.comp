#version 450
// The march's inputs, step 4: the field image (R16 unorm 0..1 <-> P.field.x..P.field.y metres, the bake's field.h),
// conservative. Jump flooding can keep a seed that is not the nearest, which only ever makes a distance too long;
// a signed distance changes by at most the distance moved, so each voxel takes the least of its own distance and
// every neighbour's distance plus the way to it (a 3x3x3 pass; it only lowers values), then less the safety
// margin (a fraction of a positive distance, since the flood's errors grow with it, plus metres). Stored rounded
// DOWN (field_to_unorm16): the stored value never exceeds the distance.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer Sdf { float sdf[]; };
layout(set = 0, binding = GROWN_BINDING_FIELD_IMAGE, r16) uniform writeonly image3D field_image;

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  ivec3 n = P.voxels.xyz;
  ivec3 v = grown_coords(id, n);
  float spacing = P.grid.y;
  float d = sdf[id];
  for (int o = 0; o < 27; ++o) {
    ivec3 off = ivec3(o % 3, (o / 3) % 3, o / 9) - 1;
    ivec3 p = v + off;
    if (o == 13 || !grown_inside_grid(p, n)) continue;
    d = min(d, sdf[grown_index(p, n)] + length(vec3(off)) * spacing);
  }
  float lo = P.field.x, hi = P.field.y;
  d = clamp(d, lo, hi);
  d -= P.field.z * max(d, 0.0) + P.field.w;
  float q = floor(clamp((d - lo) / (hi - lo), 0.0, 1.0) * 65535.0);
  if (q > 0.0 && lo + (hi - lo) * (q / 65535.0) > d) q -= 1.0;  // the division above rounded up
  imageStore(field_image, v, vec4(q / 65535.0));
}
