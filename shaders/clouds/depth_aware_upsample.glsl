// Depth-aware bilinear upsample of a lower-resolution cloud layer (colour + depth images, depth z = the
// ray's end the march clipped to: the scene's distance, the split, at most 1e6) to full-resolution
// `pixel` of `size`: each of the 4 bilinear taps is weighted by how closely its ray's end matches this
// pixel's `own_end`, so cloud marched over the sky does not bleed across a terrain silhouette into the
// pixels of the mountain in front of it (and the reverse). A tap that matches nothing keeps a trace of
// its bilinear weight, so the sum never vanishes. Used by the 40/60 Hz split's merge (the half-resolution
// near layer) and by the composite under dynamic resolution.
void depth_aware_upsample(sampler2D color_tex, sampler2D depth_tex, ivec2 pixel, ivec2 size, float own_end,
                          out vec4 color, out vec4 depth) {
  ivec2 low = textureSize(color_tex, 0);
  vec2 p = (vec2(pixel) + 0.5) * vec2(low) / vec2(size) - 0.5;
  ivec2 base = ivec2(floor(p));
  vec2 f = p - vec2(base);
  color = vec4(0.0);
  depth = vec4(0.0);
  float wsum = 0.0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      ivec2 q = clamp(base + ivec2(i, j), ivec2(0), low - 1);
      float bil = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
      vec4 d = texelFetch(depth_tex, q, 0);
      float rel = abs(d.z - own_end) / max(own_end, 1.0);
      float w = bil * exp(-rel * 20.0) + 1e-5 * bil;
      color += texelFetch(color_tex, q, 0) * w;
      depth += d * w;
      wsum += w;
    }
  color /= wsum;
  depth /= wsum;
}

// The 40/60 Hz split's merge of the near layer (upsampled: near_c, near_d) in front of the far one (far_c, far_d):
// radiance near + near transmittance x far, transmittance the product; depth x the near layer's opacity-0.5 distance
// where it is opaque enough, else the far one's; y the steps of both (the near's at a quarter of the pixels); z the far
// segment's end. split_merge.comp and reconstruct.comp (MERGE_NEAR) both merge with it.
void merge_near_over_far(vec4 near_c, vec4 near_d, vec4 far_c, vec4 far_d, out vec4 color, out vec4 depth) {
  color = vec4(near_c.rgb + near_c.a * far_c.rgb, near_c.a * far_c.a);
  depth = vec4(near_c.a < 0.5 ? near_d.x : far_d.x, near_d.y * 0.25 + far_d.y, far_d.z, 0.0);
}
