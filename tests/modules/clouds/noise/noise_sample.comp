#version 460
// clouds/noise GPU test: reads the voxel noise texture at given coordinates and LODs, so the test can
// check that the GPU decodes our R4G4B4A4 / RGBA8 bytes into the channels the CPU wrote.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform sampler3D noise_tex;
layout(set = 0, binding = 1, std430) buffer Results { vec4 results[]; };
layout(set = 0, binding = 2, std430) readonly buffer Queries { vec4 queries[]; };  // xyz = uvw, w = lod
layout(push_constant) uniform Params { uint count; } params;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.count) return;
  vec4 q = queries[i];
  results[i] = textureLod(noise_tex, q.xyz, q.w);
}
