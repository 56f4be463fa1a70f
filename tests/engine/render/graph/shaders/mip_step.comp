#version 450
// Render-graph test: one step of a mip chain built pass by pass. FIRST_LEVEL: v = x + 16 y (no source
// bound, so nothing is read before it is written); otherwise the mean of the 2x2 texels below it.
layout(local_size_x = 8, local_size_y = 8) in;
#ifndef FIRST_LEVEL
layout(set = 0, binding = 0, r32f) uniform readonly image2D src;
#endif
layout(set = 0, binding = 1, r32f) uniform writeonly image2D dst;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(dst)))) return;
#ifdef FIRST_LEVEL
  float v = float(p.x + 16 * p.y);
#else
  ivec2 s = 2 * p;
  float v = 0.25 * (imageLoad(src, s).r + imageLoad(src, s + ivec2(1, 0)).r + imageLoad(src, s + ivec2(0, 1)).r +
                    imageLoad(src, s + ivec2(1, 1)).r);
#endif
  imageStore(dst, p, vec4(v));
}
