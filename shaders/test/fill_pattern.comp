#version 460
// gpu layer test: runtime compile with an #include and a define; writes test_pattern() into an image.
#extension GL_GOOGLE_include_directive : require
#include "test/test_common.glsl"

#ifndef SCALE
#define SCALE 1.0
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba32f) uniform writeonly image2D out_image;
layout(push_constant) uniform Push { uvec2 size; } pc;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(p, pc.size))) return;
  imageStore(out_image, ivec2(p), test_pattern(p, SCALE));
}
