#version 460
// gpu layer test: samples a 3D texture with mips at given coordinates and LODs (textureLod, as
// LAVAPIPE.md advises for compute) and writes the results to a buffer.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler3D volume;
layout(set = 0, binding = 1, std430) buffer Results { vec4 results[]; };
layout(set = 0, binding = 2, std430) readonly buffer Queries { vec4 queries[]; };  // xyz = uvw, w = lod

void main() {
  uint i = gl_GlobalInvocationID.x;
  vec4 q = queries[i];
  results[i] = textureLod(volume, q.xyz, q.w);
}
