#version 460
// Test module (tests/engine/app/module_test.cpp), after-opaque stage: scales the scene colour by
// the tint the before-scene pass wrote.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform image2D hdr;
layout(set = 0, binding = 1) uniform sampler2D tint;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(hdr)))) return;
  imageStore(hdr, p, imageLoad(hdr, p) * vec4(texelFetch(tint, ivec2(0), 0).rgb, 1.0));
}
