#version 450
// One shadow map for the scene (render::LightShadowMap: the engine reads one): the envelope's (envelope_shadow.comp)
// times the voxel clouds' (shadow_map.comp), both transmittances along the same light ray. The plane is the envelope
// map's, the lower one (the voxel clouds' map is on the plane of their lowest box's bottom; a point there is carried
// along the light from this plane to it).
#extension GL_GOOGLE_include_directive : require
#include "shared/envelope_params.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = ENV_BINDING_SHADOW_IN) uniform sampler2D envelope_shadow;
layout(set = 0, binding = ENV_BINDING_VOXEL_SHADOW) uniform sampler2D voxel_shadow;
layout(set = 0, binding = ENV_BINDING_SHADOW_OUT, r16f) uniform writeonly image2D shadow_out;
layout(push_constant) uniform Push { EnvelopeShadowCombinePush pc; };

float map_at(sampler2D tex, vec4 rect, vec2 xz) {
  vec2 uv = (xz - rect.xy) / rect.zw;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
  return textureLod(tex, uv, 0.0).r;
}

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(shadow_out);
  if (any(greaterThanEqual(texel, size))) return;
  vec2 xz = pc.plane.xy + (vec2(texel) + 0.5) / vec2(size) * pc.plane.zw;
  vec3 l = normalize(pc.light.xyz);
  float T = map_at(envelope_shadow, pc.envelope, xz);
  if (pc.voxel.y > 0.5) T *= map_at(voxel_shadow, pc.voxel_plane, xz + l.xz * ((pc.voxel.x - pc.light.w) / l.y));
  imageStore(shadow_out, texel, vec4(T, 0.0, 0.0, 0.0));
}
