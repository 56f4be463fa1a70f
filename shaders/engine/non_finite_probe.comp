#version 450
// The soak's check that a frame holds no NaN or infinity (render/non_finite_probe.h), without reading the frame
// back: COUNT counts the scene colour's non-finite texels into counters.pixels; FOLD (one invocation, after it)
// turns that into a frame with non-finite texels and clears it, so the host reads four numbers per window.
#extension GL_GOOGLE_include_directive : require

#ifndef FOLD
#define FOLD 0
#endif
#if FOLD == 1
layout(local_size_x = 1) in;
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif
layout(set = 0, binding = 0, std430) buffer Counters {
  uint pixels;         // this frame's non-finite texels (COUNT adds, FOLD clears)
  uint bad_frames;     // frames with at least one
  uint bad_pixels;     // their texels, summed
  uint frames;         // frames probed
  uint first;          // this frame's first non-finite texel, y * 65536 + x (COUNT takes the least, FOLD resets it)
  uint last_first;     // the last bad frame's first non-finite texel: the soak names it
} counters;
#if FOLD == 0
layout(set = 0, binding = 1) uniform sampler2D scene_colour;
#endif

void main() {
#if FOLD == 1
  uint n = counters.pixels;
  counters.frames += 1u;
  if (n > 0u) {
    counters.bad_frames += 1u;
    counters.bad_pixels += n;
    counters.last_first = counters.first;
  }
  counters.pixels = 0u;
  counters.first = 0xffffffffu;
#else
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = textureSize(scene_colour, 0);
  if (any(greaterThanEqual(p, size))) return;
  vec4 c = texelFetch(scene_colour, p, 0);
  if (any(isnan(c)) || any(isinf(c))) {
    atomicAdd(counters.pixels, 1u);
    atomicMin(counters.first, uint(p.y) * 65536u + uint(p.x));
  }
#endif
}
