#version 450
// Temporal accumulation of the jittered cloud march (2015 talk, seed 004: temporal reprojection of the
// cloud buffer; Karis 2014 "High Quality Temporal Supersampling": neighbourhood clamp).
// Each pixel is reprojected with the cloud depth (distance where opacity reached 0.5, else the first
// cloud sample, else "at infinity": the rotation alone), the history is clamped to the plus-shaped (5-texel)
// min/max of this frame's march around the pixel (so a disocclusion or a moving cloud cannot ghost),
// and blended with weight P.misc.y for the new frame. Off-screen, behind the camera or with history
// invalid (P.misc.w == 0: first frame, resize, camera cut) the current frame is taken as is.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_CURRENT) uniform sampler2D current_tex;
layout(set = 0, binding = CLOUD_BINDING_CURRENT_DEPTH) uniform sampler2D current_depth;
layout(set = 0, binding = CLOUD_BINDING_HISTORY) uniform sampler2D history_tex;
layout(set = 0, binding = CLOUD_BINDING_ACCUM_OUT, rgba16f) uniform writeonly image2D accum_out;
layout(push_constant) uniform Push { CloudMarchPush pc; };
#include "clouds/reproject_history.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 cur = texelFetch(current_tex, pixel, 0);
  // The clamp box of the pixel and its 4 edge neighbours (a plus, not the 3x3: on a CPU device fetches
  // are the cost of this pass, and the plus bounds the same edges).
  vec4 lo = cur, hi = cur;
  const ivec2 kPlus[4] = ivec2[](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
  for (int k = 0; k < 4; ++k) {
    vec4 c = texelFetch(current_tex, clamp(pixel + kPlus[k], ivec2(0), size - 1), 0);
    lo = min(lo, c);
    hi = max(hi, c);
  }
  vec4 result = cur;
  if (P.misc.w > 0.5) {
    vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
    vec3 ro = P.camera_pos.xyz;
    vec3 rd = view_ray_dir(P.inv_view_proj, uv * 2.0 - 1.0, ro);
    float depth = texelFetch(current_depth, pixel, 0).x;
    vec2 fetch_uv;
    bool on_texel;
    if (reproject(ro, rd, depth, fetch_uv, on_texel)) result = mix(clamp(textureLod(history_tex, fetch_uv, 0.0), lo, hi), cur, P.misc.y);
  }
  imageStore(accum_out, pixel, result);
}
