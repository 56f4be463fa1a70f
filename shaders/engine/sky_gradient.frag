#version 450
// Sky pass: the gradient of sky_common.glsl plus the sun disc, only where the geometry pass left the
// depth buffer empty (reversed-Z: the pipeline tests depth EQUAL 0.0, the cleared far plane).
#extension GL_GOOGLE_include_directive : require
#include "engine/sky_common.glsl"

layout(set = 0, binding = FRAME_PARAMS_BINDING, std140) uniform FrameBlock { FrameParams frame; };
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

void main() {
  vec4 clip = vec4(in_uv * 2.0 - 1.0, 0.5, 1.0);  // any depth on the ray; 0.5 avoids the far plane
  vec4 world = frame.inv_view_proj * clip;
  vec3 dir = normalize(world.xyz / world.w - frame.camera_position);
  out_color = vec4(sky_gradient(frame, dir) + sun_disc(frame, dir), 1.0);
}
