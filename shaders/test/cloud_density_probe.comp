#version 450
// Test probe: the voxel-cloud density sampler (cloud_common.glsl's sample_density, no near-camera details,
// noise mip 0) at a list of world points, for the comparison with the CPU density query
// (modules/clouds/scene/density_query.h). P.frame.x: point count; instance 0 is the one sampled.
#extension GL_GOOGLE_include_directive : require
#include "clouds/cloud_common.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = 10, std430) readonly buffer Points { vec4 points[]; };
layout(set = 0, binding = 11, std430) writeonly buffer Densities { float densities[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= P.frame.x) return;
  CloudInstanceParams inst = P.instances[0];
  vec3 a = (inst.world_to_asset * vec4(points[i].xyz, 1.0)).xyz;
  vec3 uvw = asset_uvw(inst, a);
  float d = 0.0;
  if (all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0)))) d = sample_density(CLOUD_ASSET_0, inst, a, 1e4, 0.0, false).full;
  densities[i] = d;
}
