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
// TEMPORAL 1 (the voxel clouds' reconstruction, temporal accumulation on): the pass also accumulates its result (the
// merged one with MERGE_NEAR) as temporal_accumulate.comp does, one full-resolution pass less (issue 23): the history
// reprojected with this frame's cloud depth, clamped to the min/max of the pixel's bilinear 2x2 of marched samples and
// its own result (temporal_accumulate.comp takes the plus of its input, which this pass is still writing; the
// reconstruction's wider box, with the own block's plus, let a moving camera smear: fly_out_of_flank frame 300 at 41.9
// dB from the separate pass, 44.9 with this one), and blended with weight P.misc.y for the new frame; P.misc.w = 0: no
// history.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#ifndef CLIP_TO_SPLIT
#define CLIP_TO_SPLIT 0  // 1: the 40/60 Hz near segment (half resolution), whose rays end at the split distance
#endif
#ifndef MERGE_NEAR
#define MERGE_NEAR 0  // 1: the 40/60 Hz far segment, merged with the near layer here (split_merge.comp's work, one pass less)
#endif
#ifndef TEMPORAL
#define TEMPORAL 0  // 1: the temporal accumulation of the result here (temporal_accumulate.comp's work, one pass less)
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
#if TEMPORAL
layout(set = 0, binding = CLOUD_BINDING_RECON_TEMPORAL_HISTORY) uniform sampler2D temporal_history;
layout(set = 0, binding = CLOUD_BINDING_RECON_TEMPORAL_OUT, rgba16f) uniform writeonly image2D temporal_out;
#endif
layout(push_constant) uniform Push { CloudMarchPush pc; };

#include "clouds/reproject_history.glsl"

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

  // Bilinear upsample of the marched samples (sample (i, j) sits at pixel (i, j) * B + offset; the marched pixel's own
  // sample with weight 1), and the clamp box: the 4 bilinear samples (they include this pixel's own block) and the own
  // block's 4 edge neighbours (a plus rather than the 3x3: fetches are this pass's cost on a CPU device).
  vec2 sp = (vec2(pixel - offset)) / float(B);
  ivec2 b0 = ivec2(floor(sp));
  vec2 f = sp - vec2(b0);
  vec4 s00 = texelFetch(sub_color, clamp(b0, ivec2(0), ss - 1), 0);
  vec4 s10 = texelFetch(sub_color, clamp(b0 + ivec2(1, 0), ivec2(0), ss - 1), 0);
  vec4 s01 = texelFetch(sub_color, clamp(b0 + ivec2(0, 1), ivec2(0), ss - 1), 0);
  vec4 s11 = texelFetch(sub_color, clamp(b0 + ivec2(1, 1), ivec2(0), ss - 1), 0);
  vec4 lo = min(min(s00, s10), min(s01, s11)), hi = max(max(s00, s10), max(s01, s11));
#if TEMPORAL
  vec4 t_lo = lo, t_hi = hi;  // the temporal accumulation's box: the bilinear samples around the pixel only
#endif
  const ivec2 kPlus[4] = ivec2[](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
  for (int k = 0; k < 4; ++k) {
    vec4 c = texelFetch(sub_color, clamp(block + kPlus[k], ivec2(0), ss - 1), 0);
    lo = min(lo, c);
    hi = max(hi, c);
  }
  vec4 result = own;
  if (pixel - block * B != offset) {
    result = mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
    vec2 fetch_uv;
    bool on_texel;
    if (pc.sub.w > 0.5 && reproject(ro, rd, own_d.x, fetch_uv, on_texel)) {  // history valid, and on screen
      vec4 hist = textureLod(history_tex, fetch_uv, 0.0);
      // pc.sub.w = 2 (ReconstructInputs::settled): a history landing exactly on its texel (a still camera) is this
      // pixel's own march in the same picture; the clamp to the marched neighbours 4 px away would only cut its
      // detail (the 1-in-16 reprojection's picture was 31 dB from marching every pixel, now the same).
      result = pc.sub.w > 1.5 && on_texel ? hist : clamp(hist, lo, hi);
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
#if TEMPORAL
  // The box merged as the colour is (near over each corner of the far one's).
  vec4 cur = color;
  float cur_depth = depth.x;
  t_lo = vec4(near_c.rgb + near_c.a * t_lo.rgb, near_c.a * t_lo.a);
  t_hi = vec4(near_c.rgb + near_c.a * t_hi.rgb, near_c.a * t_hi.a);
#endif
#else
  imageStore(out_depth, pixel, far_d);
#if TEMPORAL
  vec4 cur = result;
  float cur_depth = own_d.x;
#endif
#endif
#if TEMPORAL
  vec4 accumulated = cur;
  vec2 t_uv;
  bool t_on_texel;
  if (P.misc.w > 0.5 && reproject(ro, rd, cur_depth, t_uv, t_on_texel)) {
    vec4 hist = textureLod(temporal_history, t_uv, 0.0);
    accumulated = mix(clamp(hist, min(t_lo, cur), max(t_hi, cur)), cur, P.misc.y);
  }
  imageStore(temporal_out, pixel, accumulated);
#endif
}
