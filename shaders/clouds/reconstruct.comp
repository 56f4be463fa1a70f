#version 450
// Temporal reprojection of a sub-sampled march (2015 talk, seed 004: "we render 1 of 16 pixels per
// frame" and reproject the rest from the last frame's cloud buffer). The full-resolution march (the
// 30 Hz march, or the 40/60 Hz far segment) runs on one pixel of every BxB block per frame
// (B = CloudMarchPush::sub.x, the marched pixel's offset in its block sub.yz, cycling over the block
// in B*B frames); this pass rebuilds the full-resolution image:
//   - the marched pixel of a block takes this frame's value as is (talk: the new pixel replaces);
//   - every other pixel reprojects its own history (last frame's reconstruction) with this frame's cloud
//     depth of its block (x: opacity-0.5 distance, else "at infinity"), clamped to the min/max of the
//     marched blocks around it (its bilinear 2x2 and the own block's plus) (no ghost where a cloud moved or was disoccluded);
//   - off-screen, behind the camera or with no history: the bilinear upsample of this frame's samples.
// Depth out: x, y of the block's marched pixel (y = steps: the cost of this frame), z recomputed per
// pixel from the scene depth (the split merge's depth-aware upsample needs it per pixel).
// MERGE_NEAR 1 (the 40/60 Hz far segment): the near layer is merged in here, as split_merge.comp does, and the pass
// writes the far history and the merged colour and depth (no far depth: only the merge read it).
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#ifndef CLIP_TO_SPLIT
#define CLIP_TO_SPLIT 0  // 1: the 40/60 Hz near segment (half resolution), whose rays end at the split distance
#endif
#ifndef MERGE_NEAR
#define MERGE_NEAR 0  // 1: the 40/60 Hz far segment, merged with the near layer here (split_merge.comp's work, one pass less)
#endif
#include "engine/runtime_uniform.glsl"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_CURRENT) uniform sampler2D sub_color;
layout(set = 0, binding = CLOUD_BINDING_CURRENT_DEPTH) uniform sampler2D sub_depth;
layout(set = 0, binding = CLOUD_BINDING_HISTORY) uniform sampler2D history_tex;
layout(set = 0, binding = CLOUD_BINDING_ACCUM_OUT, rgba16f) uniform writeonly image2D out_color;
layout(set = 0, binding = CLOUD_BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;
#if MERGE_NEAR
#include "clouds/depth_aware_upsample.glsl"
layout(set = 0, binding = CLOUD_BINDING_RECON_NEAR) uniform sampler2D near_tex;
layout(set = 0, binding = CLOUD_BINDING_RECON_NEAR_DEPTH) uniform sampler2D near_depth;
layout(set = 0, binding = CLOUD_BINDING_RECON_MERGED, rgba16f) uniform writeonly image2D merged;
layout(set = 0, binding = CLOUD_BINDING_RECON_MERGED_DEPTH, rgba32f) uniform writeonly image2D merged_depth;
#else
layout(set = 0, binding = CLOUD_BINDING_OUT_DEPTH, rgba32f) uniform writeonly image2D out_depth;
#endif
layout(push_constant) uniform Push { CloudMarchPush pc; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  int B = runtime_int(pc.sub.x);
  ivec2 offset = runtime_ivec2(pc.sub.yz);
  ivec2 ss = textureSize(sub_color, 0);
  ivec2 block = pixel / B;
  vec4 own = texelFetch(sub_color, block, 0);
  vec4 own_d = texelFetch(sub_depth, block, 0);

  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = P.camera_pos.xyz;
  vec3 rd = view_ray_dir(P.inv_view_proj, ndc, ro);
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_end = 1e30;
  if (d > 0.0) {
    vec4 w = P.inv_view_proj * vec4(ndc, d, 1.0);
    t_end = distance(w.xyz / w.w, ro);
  }
#if CLIP_TO_SPLIT
  t_end = min(t_end, P.steps.x);  // the near segment's rays end at the split (the merge compares these ends)
#endif

  vec4 result = own;
  if (pixel - block * B != offset) {
    // Bilinear upsample of the marched samples (sample (i, j) sits at pixel (i, j) * B + offset).
    vec2 sp = (vec2(pixel - offset)) / float(B);
    ivec2 b0 = ivec2(floor(sp));
    vec2 f = sp - vec2(b0);
    vec4 s00 = texelFetch(sub_color, clamp(b0, ivec2(0), ss - 1), 0);
    vec4 s10 = texelFetch(sub_color, clamp(b0 + ivec2(1, 0), ivec2(0), ss - 1), 0);
    vec4 s01 = texelFetch(sub_color, clamp(b0 + ivec2(0, 1), ivec2(0), ss - 1), 0);
    vec4 s11 = texelFetch(sub_color, clamp(b0 + ivec2(1, 1), ivec2(0), ss - 1), 0);
    vec4 up = mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
    result = up;
    if (pc.sub.w > 0.5) {  // history valid
      // Clamp box: the 4 bilinear samples (they include this pixel's own block) and the own block's 4
      // edge neighbours (a plus rather than the 3x3: fetches are this pass's cost on a CPU device).
      vec4 lo = min(min(s00, s10), min(s01, s11)), hi = max(max(s00, s10), max(s01, s11));
      const ivec2 kPlus[4] = ivec2[](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
      for (int k = 0; k < 4; ++k) {
        vec4 c = texelFetch(sub_color, clamp(block + kPlus[k], ivec2(0), ss - 1), 0);
        lo = min(lo, c);
        hi = max(hi, c);
      }
      float depth = own_d.x;
      vec4 world = depth < 1e5 ? vec4(ro + rd * depth, 1.0) : vec4(rd, 0.0);
      vec4 prev = P.prev_view_proj * world;
      if (prev.w > 0.0) {
        vec2 prev_uv = prev.xy / prev.w * 0.5 + 0.5;
        if (all(greaterThanEqual(prev_uv, vec2(0.0))) && all(lessThanEqual(prev_uv, vec2(1.0)))) {
          vec2 prev_px = prev_uv * pc.target.xy - 0.5;
          vec2 snapped = round(prev_px);
          bool on_texel = all(lessThan(abs(prev_px - snapped), vec2(0.01)));
          vec2 fetch_uv = on_texel ? (snapped + 0.5) * pc.target.zw : prev_uv;
          vec4 hist = textureLod(history_tex, fetch_uv, 0.0);
          // pc.sub.w = 2 (ReconstructInputs::settled): a history landing exactly on its texel (a still camera) is this
          // pixel's own march in the same picture; the clamp to the marched neighbours 4 px away would only cut its
          // detail (the 1-in-16 reprojection's picture was 31 dB from marching every pixel, now the same).
          result = pc.sub.w > 1.5 && on_texel ? hist : clamp(hist, lo, hi);
        }
      }
    }
  }
  imageStore(out_color, pixel, result);
  vec4 far_d = vec4(own_d.x, own_d.y, min(t_end, 1e6), 0.0);
#if MERGE_NEAR
  // split_merge.comp's merge (its debug views keep that pass): the near layer upsampled depth-aware against this
  // pixel's near-segment end, composited in front of the far one.
  vec4 near_c, near_dv, color, depth;
  depth_aware_upsample(near_tex, near_depth, pixel, size, min(P.steps.x, far_d.z), near_c, near_dv);
  merge_near_over_far(near_c, near_dv, result, far_d, color, depth);
  imageStore(merged, pixel, color);
  imageStore(merged_depth, pixel, depth);
#else
  imageStore(out_depth, pixel, far_d);
#endif
}
