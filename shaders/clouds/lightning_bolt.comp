#version 450
// The visible channel of ground discharges (issue 9): the bolts' segments (gameplay::lightning_bolt, a
// branching path from the flash down to the ground) drawn as light over the scene after the clouds.
// Per pixel, the view ray's closest approach to each segment gives a Gaussian core of the channel's
// radius, widened to a pixel far away with its energy kept (core / width), plus a faint glow of the air
// around it. A segment behind the scene depth is hidden; behind the cloud's half-opacity depth it is seen
// through the cloud's transmittance (the part of the channel inside the cloud shows as a glow in it).
// Dispatched over the bolts' screen rectangle only (CloudEffectsPush::rect).
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "engine/view_ray.glsl"
#include "engine/runtime_uniform.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_FX_PARAMS, std140) uniform EffectsBlock { CloudEffectsParams F; };
layout(set = 0, binding = CLOUD_BINDING_FX_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = CLOUD_BINDING_FX_CLOUDS) uniform sampler2D cloud_color;
layout(set = 0, binding = CLOUD_BINDING_FX_CLOUD_DEPTH) uniform sampler2D cloud_depth;
layout(set = 0, binding = CLOUD_BINDING_FX_HDR, rgba16f) uniform image2D hdr;
layout(push_constant) uniform Push { CloudEffectsPush pc; };

void main() {
  // The parameters (every bolt's rectangle, segment count and flags differ) kept out of lavapipe's inlining
  // (runtime_uniform.glsl): `cumulo soak` measured a compiled copy kept per bolt, +9 MB of resident memory per
  // 100 frames of lightning.
  ivec2 rect_xy = runtime_ivec2(vec2(pc.rect.xy)), rect_zw = runtime_ivec2(vec2(pc.rect.zw));
  uint segments = runtime_uint(F.counts.x);
  float clouds_on = F.misc.y + runtime_zero();
  ivec2 pixel = rect_xy + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(ivec2(gl_GlobalInvocationID.xy), rect_zw)) || any(greaterThanEqual(pixel, runtime_ivec2(F.viewport.xy))))
    return;
  vec2 uv = (vec2(pixel) + 0.5) * F.viewport.zw;
  vec2 ndc = uv * 2.0 - 1.0;
  vec3 ro = F.camera_pos.xyz;
  vec3 rd = view_ray_dir(F.inv_view_proj, ndc, ro);
  float d = textureLod(scene_depth, uv, 0.0).r;
  float t_scene = 1e30;
  if (d > 0.0) {
    vec4 w = F.inv_view_proj * vec4(ndc, d, 1.0);
    t_scene = distance(w.xyz / w.w, ro);
  }
  float cloud_t = 1.0, cloud_d = 1e30;
  if (clouds_on > 0.5) {
    cloud_t = textureLod(cloud_color, uv, 0.0).a;
    cloud_d = textureLod(cloud_depth, uv, 0.0).x;
  }
  float core = F.bolt.w + runtime_zero();
  float sum = 0.0;
  for (uint i = 0u; i < segments; ++i) {
    vec3 a = F.seg_a[i].xyz, v = F.seg_b[i].xyz - a, w0 = ro - a;
    float b = dot(rd, v), c = dot(v, v), dd = dot(rd, w0), e = dot(v, w0);
    float den = c - b * b;
    float s = den > 1e-6 ? clamp((e - b * dd) / den, 0.0, 1.0) : 0.0;
    float t = max(b * s - dd, 0.0);
    s = clamp(dot(ro + rd * t - a, v) / max(c, 1e-6), 0.0, 1.0);
    vec3 q = a + v * s;
    t = max(dot(q - ro, rd), 0.0);
    if (t > t_scene) continue;
    float dist = distance(ro + rd * t, q);
    float width = max(core, t * F.misc.x * 0.7);
    float x = dist / width;
    float value = F.seg_a[i].w * (exp(-x * x) * (core / width) + 0.0005 * exp(-dist / 15.0));
    sum += cloud_d < t ? value * cloud_t : value;
  }
  vec4 c0 = imageLoad(hdr, pixel);
  imageStore(hdr, pixel, vec4(c0.rgb + F.bolt.rgb * sum, c0.a));
}
