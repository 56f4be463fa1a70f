#version 450
// Cloud composite over the scene colour, before tonemap (issue 8 pass 5; DESIGN.md "composite"):
// hdr = hdr * transmittance + in-scattered radiance. With no cloud (transmittance exactly 1, radiance
// exactly 0) the scene is left bit-exact. The sun and ambient colours were already applied by the
// march (CloudFrameInputs). Aerial perspective (2017 talk: the clouds blend into the distance): the
// cloud is seen through the same height fog as the terrain (sky_common.glsl's fog_amount) at its
// half-opacity depth, fading toward the sky's gradient colour in its direction:
//   hdr = hdr * T + (1 - f) * radiance + f * (1 - T) * sky.
// Debug views (P.frame.w): profile and split arrive opaque from the march/merge (alpha 0); steps maps
// the march's step count (depth image y) to a blue..red heat map over P.march.w steps; light-grid shows
// a horizontal slice of instance 0's grid at height P.misc.z (0..1): red = sun transmittance
// exp(-extinction * summed density), green = the same toward the sky.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_CLOUDS) uniform sampler2D clouds_tex;
layout(set = 0, binding = CLOUD_BINDING_HDR, rgba16f) uniform image2D hdr;
layout(set = 0, binding = CLOUD_BINDING_DEBUG_GRID) uniform sampler3D debug_grid;
layout(set = 0, binding = CLOUD_BINDING_CLOUD_DEPTH) uniform sampler2D cloud_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };

vec3 heat(float x) {
  x = clamp(x, 0.0, 1.0);
  return clamp(vec3(1.5 - abs(4.0 * x - 3.0), 1.5 - abs(4.0 * x - 2.0), 1.5 - abs(4.0 * x - 1.0)), 0.0, 1.0);
}

// The terrain's haze (sky_common.glsl fog_amount, sky_gradient without the sun's glow) at distance `dist`.
float haze_amount(vec3 ro, vec3 dir, float dist) {
  float density = P.haze.x, falloff = max(P.haze.y, 1e-6);
  float dy = dir.y * dist;
  float integral = abs(dy) > 1e-3 ? (exp(-falloff * ro.y) - exp(-falloff * (ro.y + dy))) / (falloff * dir.y)
                                  : dist * exp(-falloff * ro.y);
  return 1.0 - exp(-density * max(integral, 0.0));
}
vec3 haze_colour(vec3 dir) { return mix(P.sky_horizon.rgb, P.sky_zenith.rgb, pow(clamp(dir.y, 0.0, 1.0), 0.5)); }

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec2 uv = (vec2(pixel) + 0.5) * pc.target.zw;
  vec4 c = texelFetch(clouds_tex, pixel, 0);
  vec4 scene = imageLoad(hdr, pixel);
  vec3 rgb = scene.rgb * c.a + c.rgb;
  float depth50 = texelFetch(cloud_depth, pixel, 0).x;
  if (c.a < 1.0 && depth50 < 1e5 && P.haze.x > 0.0) {
    vec4 h = P.inv_view_proj * vec4(uv * 2.0 - 1.0, 0.5, 1.0);
    vec3 ro = P.camera_pos.xyz;
    vec3 dir = normalize(h.xyz / h.w - ro);
    float f = haze_amount(ro, dir, depth50);
    rgb = scene.rgb * c.a + (1.0 - f) * c.rgb + f * (1.0 - c.a) * haze_colour(dir);
  }
  uint view = P.frame.w;
  if (view == CLOUD_DEBUG_STEPS) {
    rgb = heat(texelFetch(cloud_depth, pixel, 0).y / max(P.march.w, 1.0));
  } else if (view == CLOUD_DEBUG_LIGHT_GRID) {
    vec2 g = textureLod(debug_grid, vec3(uv.x, P.misc.z, uv.y / float(max(P.frame.y, 1u))), 0.0).xy;
    rgb = vec3(exp(-g.x * P.march.x), exp(-g.y * P.march.x), 0.0);
  }
  imageStore(hdr, pixel, vec4(rgb, scene.a));
}
