#version 450
// Geometry pass vertex stage: glTF meshes (position, normal, uv) placed by their node transform.
#extension GL_GOOGLE_include_directive : require
#include "shared/frame_params.h"

layout(set = 0, binding = FRAME_PARAMS_BINDING, std140) uniform FrameBlock { FrameParams frame; };
layout(push_constant, std430) uniform DrawBlock { DrawParams draw; };

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec2 out_normal_uv;  // a height field's normal map (DrawParams normal_plane_*)

void main() {
  vec4 world = draw.model * vec4(in_position, 1.0);
  out_world = world.xyz;
  out_normal = mat3(draw.model) * in_normal;  // uniform scale: no inverse-transpose needed
  out_uv = in_uv;
  out_normal_uv = vec2(dot(vec4(in_position, 1.0), draw.normal_plane_u), dot(vec4(in_position, 1.0), draw.normal_plane_v));
  gl_Position = frame.view_proj * world;
}
