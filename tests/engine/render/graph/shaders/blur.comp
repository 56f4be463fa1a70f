#version 450
// Render-graph test: 3x3 box blur with clamp-to-edge, reading a sampled image, writing a storage image.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D src;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D dst;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(dst);
  if (any(greaterThanEqual(p, size))) return;
  float sum = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) sum += texelFetch(src, clamp(p + ivec2(dx, dy), ivec2(0), size - 1), 0).r;
  imageStore(dst, p, vec4(sum / 9.0));
}
