#version 450
// The march's inputs, the profile depth (grown_attributes.cpp): the depth below the surface, max(0, -sdf), run
// through a max filter of +-P.radii.x voxels along one axis a pass (pc.pass.y: x reads the distance, y and z the
// pass before); after z, thickness factor x that, clamped to [min, max] profile depth: a thin sheet reaches 1 in
// its middle, a tower's core at the talk-scale ramp.
#extension GL_GOOGLE_include_directive : require
#include "clouds/grow/grown_asset_common.glsl"

layout(local_size_x = GROWN_LOCAL_SIZE) in;
layout(set = 0, binding = 1, std430) readonly buffer In { float depth_in[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Out { float depth_out[]; };

void main() {
  int id = int(gl_GlobalInvocationID.x);
  if (id >= P.voxels.w) return;
  ivec3 n = P.voxels.xyz;
  ivec3 v = grown_coords(id, n);
  int axis = grown_runtime(pc.pass.y), r = grown_runtime(P.radii.x);
  int stride = axis == 0 ? 1 : (axis == 1 ? n.x : n.x * n.y);
  int i = v[axis];
  bool from_sdf = axis == 0;
  float m = from_sdf ? max(0.0, -depth_in[id]) : depth_in[id];
  for (int k = max(0, i - r); k <= min(n[axis] - 1, i + r); ++k) {
    float d = depth_in[id + (k - i) * stride];
    m = max(m, from_sdf ? max(0.0, -d) : d);
  }
  if (axis == 2) m = clamp(P.profile.x * m, P.profile.y, P.profile.z);
  depth_out[id] = m;
}
