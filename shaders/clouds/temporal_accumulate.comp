#version 450
// Temporal accumulation of the jittered cloud march (2015 talk, seed 004: temporal reprojection of the
// cloud buffer; Karis 2014 "High Quality Temporal Supersampling": neighbourhood clamp).
// Each pixel is reprojected with the cloud depth (distance where opacity reached 0.5, else the first
// cloud sample, else "at infinity": the rotation alone), the history is clamped to the 3x3
// min/max of this frame's march around the pixel (so a disocclusion or a moving cloud cannot ghost),
// and blended with weight P.misc.y for the new frame. Off-screen, behind the camera or with history
// invalid (P.misc.w == 0: first frame, resize, camera cut) the current frame is taken as is.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_CURRENT) uniform sampler2D current_tex;
layout(set = 0, binding = CLOUD_BINDING_CURRENT_DEPTH) uniform sampler2D current_depth;
layout(set = 0, binding = CLOUD_BINDING_HISTORY) uniform sampler2D history_tex;
layout(set = 0, binding = CLOUD_BINDING_ACCUM_OUT, rgba16f) uniform writeonly image2D accum_out;
layout(push_constant) uniform Push { CloudMarchPush pc; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 cur = texelFetch(current_tex, pixel, 0);
  vec4 lo = cur, hi = cur;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      vec4 c = texelFetch(current_tex, clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1), 0);
      lo = min(lo, c);
      hi = max(hi, c);
    }
  vec4 result = cur;
  if (P.misc.w > 0.5) {
    vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
    vec4 h = P.inv_view_proj * vec4(uv * 2.0 - 1.0, 0.5, 1.0);
    vec3 ro = P.camera_pos.xyz;
    vec3 rd = normalize(h.xyz / h.w - ro);
    float depth = texelFetch(current_depth, pixel, 0).x;
    // "At infinity": a point far enough that the camera's translation does not matter.
    vec4 world = depth < 1e5 ? vec4(ro + rd * depth, 1.0) : vec4(rd, 0.0);
    vec4 prev = P.prev_view_proj * world;
    if (prev.w > 0.0) {
      vec2 prev_uv = prev.xy / prev.w * 0.5 + 0.5;
      if (all(greaterThanEqual(prev_uv, vec2(0.0))) && all(lessThanEqual(prev_uv, vec2(1.0)))) {
        // A still camera reprojects onto texel centres up to float error: fetch that texel, since
        // bilinear weights of 0.999/0.001 would blur the history a little more every frame.
        vec2 prev_px = prev_uv * pc.target.xy - 0.5;
        vec2 snapped = round(prev_px);
        vec4 hist = all(lessThan(abs(prev_px - snapped), vec2(0.01)))
                        ? texelFetch(history_tex, clamp(ivec2(snapped), ivec2(0), size - 1), 0)
                        : textureLod(history_tex, prev_uv, 0.0);
        hist = clamp(hist, lo, hi);
        result = mix(hist, cur, P.misc.y);
      }
    }
  }
  imageStore(accum_out, pixel, result);
}
