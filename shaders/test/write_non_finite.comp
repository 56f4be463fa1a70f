#version 460
// Test of render/non_finite_probe.h (tests/engine/render/non_finite_probe_test.cpp): writes pc.value (a NaN, an
// infinity or a finite colour) into pc.count texels of the first row of the scene colour.
layout(local_size_x = 1) in;
layout(set = 0, binding = 0, rgba16f) uniform image2D hdr;
layout(push_constant) uniform Push { uint bits; int count; } pc;

void main() {
  for (int x = 0; x < pc.count; ++x) imageStore(hdr, ivec2(x, 0), vec4(uintBitsToFloat(pc.bits), 0.0, 0.0, 1.0));
}
