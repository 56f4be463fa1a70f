#version 450
// The path-traced reference's accumulation -> the scene colour: the mean radiance of the samples so far
// (the engine's tonemap then draws it like any frame).
#extension GL_GOOGLE_include_directive : require
#include "shared/reference_params.h"

layout(local_size_x = REF_LOCAL_SIZE, local_size_y = REF_LOCAL_SIZE) in;
layout(set = 0, binding = REF_BINDING_ACCUM, rgba32f) uniform readonly image2D accum_img;
layout(set = 0, binding = REF_BINDING_AUX, rgba32f) uniform readonly image2D aux_img;
layout(set = 0, binding = REF_BINDING_HDR, rgba16f) uniform writeonly image2D hdr;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(hdr)))) return;
  float n = max(imageLoad(aux_img, p).y, 1.0);
  // fp16 holds 65504: clamp so a firefly of the running mean cannot become inf in the scene colour.
  imageStore(hdr, p, vec4(min(imageLoad(accum_img, p).rgb / n, vec3(60000.0)), 1.0));
}
