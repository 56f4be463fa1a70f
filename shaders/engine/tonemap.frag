#version 450
// Tonemap pass: HDR scene colour -> display. ACES filmic curve in Krzysztof Narkowicz's fitted form
// ("ACES Filmic Tone Mapping Curve", 2016: a=2.51 b=0.03 c=2.43 d=0.59 e=0.14), Reinhard as the
// alternative. Encodes sRGB in the shader when the output format is UNORM (offscreen screenshots).
#extension GL_GOOGLE_include_directive : require
#include "shared/frame_params.h"

layout(set = 0, binding = TONEMAP_HDR_BINDING) uniform sampler2D hdr_color;
layout(push_constant, std430) uniform TonemapBlock { TonemapParams tm; };
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

vec3 aces_fitted(vec3 x) {
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 linear_to_srgb(vec3 c) {
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
  vec3 hdr = texelFetch(hdr_color, ivec2(gl_FragCoord.xy), 0).rgb * tm.exposure;
  vec3 ldr = tm.op == TONEMAP_ACES ? aces_fitted(hdr) : hdr / (1.0 + hdr);
  if (tm.output_srgb == 0u) ldr = linear_to_srgb(ldr);
  out_color = vec4(ldr, 1.0);
}
