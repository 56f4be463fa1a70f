#version 450
// 40/60 Hz split merge (2023 talk, seed 000 "30hz, 60hz, 40hz": "Render Split into 2 passes: < 200
// Meters: 480px * 270px, > 200 Meters: 960px * 540px"). The near segment was marched at half
// resolution, the far one at full; here the near layer is upsampled depth-aware and composited in
// front of the far one: radiance = near.rgb + near.a * far.rgb, transmittance = near.a * far.a.
// Depth-aware (depth_aware_upsample.glsl): of the 4 bilinear half-resolution taps, each is weighted by how
// closely its clipped near-segment end (depth image z: min(split, scene distance)) matches this pixel's,
// so near cloud does not bleed across a terrain silhouette into the pixels next to it.
#extension GL_GOOGLE_include_directive : require
#include "shared/cloud_params.h"
#include "clouds/depth_aware_upsample.glsl"

layout(local_size_x = CLOUD_LOCAL_SIZE, local_size_y = CLOUD_LOCAL_SIZE) in;
layout(set = 0, binding = CLOUD_BINDING_PARAMS, std140) uniform CloudBlock { CloudParams P; };
layout(set = 0, binding = CLOUD_BINDING_NEAR) uniform sampler2D near_tex;
layout(set = 0, binding = CLOUD_BINDING_NEAR_DEPTH) uniform sampler2D near_depth;
layout(set = 0, binding = CLOUD_BINDING_FAR) uniform sampler2D far_tex;
layout(set = 0, binding = CLOUD_BINDING_FAR_DEPTH) uniform sampler2D far_depth;
layout(set = 0, binding = CLOUD_BINDING_MERGED, rgba16f) uniform writeonly image2D merged;
layout(set = 0, binding = CLOUD_BINDING_MERGED_DEPTH, rgba32f) uniform writeonly image2D merged_depth;
layout(push_constant) uniform Push { CloudMarchPush pc; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pc.target.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 far_c = texelFetch(far_tex, pixel, 0);
  vec4 far_d = texelFetch(far_depth, pixel, 0);
  // This pixel's near-segment end: min(split, scene distance along the ray) = min(split, far_d.z).
  float own_end = min(P.steps.x, far_d.z);

  vec4 near_c, near_dv;
  depth_aware_upsample(near_tex, near_depth, pixel, size, own_end, near_c, near_dv);

  vec4 color, depth;
  merge_near_over_far(near_c, near_dv, far_c, far_d, color, depth);
  if (P.frame.w == CLOUD_DEBUG_SPLIT) {
    // Opacity of each layer: near in orange, far in blue.
    color = vec4((1.0 - near_c.a) * vec3(1.0, 0.45, 0.1) + near_c.a * (1.0 - far_c.a) * vec3(0.1, 0.35, 1.0), 0.0);
  } else if (P.frame.w == CLOUD_DEBUG_PROFILE) {
    color = vec4(1.0 - (1.0 - near_c.rgb) * (1.0 - far_c.rgb), 0.0);
  }
  imageStore(merged, pixel, color);
  imageStore(merged_depth, pixel, depth);
}
