#version 460
// gpu layer test: samples a 2D texture (e.g. BC1-compressed) at given coordinates and LODs.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(set = 0, binding = 1, std430) buffer Results { vec4 results[]; };
layout(set = 0, binding = 2, std430) readonly buffer Queries { vec4 queries[]; };  // xy = uv, w = lod

void main() {
  uint i = gl_GlobalInvocationID.x;
  results[i] = textureLod(tex, queries[i].xy, queries[i].w);
}
