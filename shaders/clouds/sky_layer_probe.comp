#version 450
// The 2.5D sky's density (sky_layer_density.glsl, full detail) at a list of world points: SkyLayer's
// probe, for tests and debugging (the yield's continuity at a voxel box's border is measured with it).
#extension GL_GOOGLE_include_directive : require
#include "clouds/sky_layer_density.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = SKY_BINDING_PROBE_POINTS, std430) readonly buffer Points { vec4 points[]; };
layout(set = 0, binding = SKY_BINDING_PROBE_OUT, std430) writeonly buffer Densities { float densities[]; };
layout(push_constant) uniform Push { uvec4 count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count.x) return;
  densities[i] = density(points[i].xyz, false);
}
