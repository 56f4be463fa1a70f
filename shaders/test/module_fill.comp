#version 460
// Test module (tests/engine/app/module_test.cpp), before-scene stage: writes the tint that the
// after-opaque pass applies, so a test sees that passes at two stages ran, in order.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0, rgba16f) uniform writeonly image2D tint;
layout(push_constant) uniform Push { vec4 color; } pc;

void main() { imageStore(tint, ivec2(0), pc.color); }
