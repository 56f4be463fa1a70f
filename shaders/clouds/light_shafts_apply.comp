#version 450
// Light shafts, step 2 (2017 talk: "we use this intensity buffer as a mask when we apply the Mie
// scattering in our atmospheric scattering shader which is only applied at larger distances"): the
// Mie in-scattering of the sun along the view ray, in the same height haze the terrain and clouds are
// hazed with (its optical depth up to the surface, the cloud's half-opacity depth, or S.misc.x for the
// sky), is scaled by the shaft intensity: where clouds or terrain shadow the air, that part of the
// in-scattering is taken out, so lit columns stand out as shafts. The removal scales the pixel (no hue
// shift where the haze model's Mie estimate exceeds what the sky holds) and keeps at least S.misc.y of it.
// Near scenery has little haze in front of it, so shafts are never drawn over it.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "clouds/cloud_math.glsl"
#include "engine/view_ray.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = SHAFT_BINDING_PARAMS, std140) uniform ShaftBlock { CloudShaftParams S; };
layout(set = 0, binding = SHAFT_BINDING_DEPTH) uniform sampler2D scene_depth;
layout(set = 0, binding = SHAFT_BINDING_CLOUDS) uniform sampler2D clouds_tex;
layout(set = 0, binding = SHAFT_BINDING_CLOUD_DEPTH) uniform sampler2D cloud_depth;
layout(set = 0, binding = SHAFT_BINDING_SHAFTS) uniform sampler2D shafts_tex;
layout(set = 0, binding = SHAFT_BINDING_HDR, rgba16f) uniform image2D hdr;
layout(push_constant) uniform Push { CloudMarchPush pc; };


// The height haze's optical depth along the ray (sky_common.glsl's fog_amount integral).
float haze_depth(vec3 ro, vec3 dir, float dist) {
  float falloff = max(S.mie.w, 1e-6);
  float dy = dir.y * dist;
  float integral = abs(dy) > 1e-3 ? (exp(-falloff * ro.y) - exp(-falloff * (ro.y + dy))) / (falloff * dir.y)
                                  : dist * exp(-falloff * ro.y);
  return S.mie.z * max(integral, 0.0);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec3 ro = S.camera_pos.xyz;
  vec3 dir = view_ray_dir(S.inv_view_proj, uv * 2.0 - 1.0, ro);
  float mu = dot(dir, S.sun_dir.xyz);
  float dist = S.misc.x;
  float d = texelFetch(scene_depth, pixel, 0).r;
  if (d > 0.0) {
    vec4 w = S.inv_view_proj * vec4(uv * 2.0 - 1.0, d, 1.0);
    dist = distance(w.xyz / w.w, ro);
  }
  // By uv, nearest: the clouds may be below the output's size (dynamic resolution).
  if (textureLod(clouds_tex, uv, 0.0).a < 0.5) dist = min(dist, textureLod(cloud_depth, uv, 0.0).x);
  float inscatter = 1.0 - exp(-haze_depth(ro, dir, dist));
  vec3 mie = S.sun_color.rgb * henyey_greenstein(mu, S.mie.x) * inscatter * S.mie.y;
  float shafts = textureLod(shafts_tex, uv, 0.0).r;
  vec4 c = imageLoad(hdr, pixel);
  const vec3 kLum = vec3(0.2126, 0.7152, 0.0722);
  float removed = dot(mie, kLum) * (1.0 - shafts) / max(dot(c.rgb, kLum), 1e-6);
  vec3 rgb = c.rgb * max(1.0 - removed, S.misc.y);
  imageStore(hdr, pixel, vec4(rgb, c.a));
}
