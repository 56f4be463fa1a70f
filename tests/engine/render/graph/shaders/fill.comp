#version 450
// Render-graph test: writes a known pattern, v(x, y) = 0.01 x + 0.1 y + frame.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform writeonly image2D dst;
layout(push_constant) uniform Push { float frame; } pc;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(dst)))) return;
  imageStore(dst, p, vec4(0.01 * float(p.x) + 0.1 * float(p.y) + pc.frame));
}
