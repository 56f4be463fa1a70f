#version 450
// Render-graph test: out = 2 * blurred (storage read) + bias (sampled, imported).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D blurred;
layout(set = 0, binding = 1) uniform sampler2D bias;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D dst;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(dst)))) return;
  imageStore(dst, p, vec4(2.0 * imageLoad(blurred, p).r + texelFetch(bias, p, 0).r));
}
