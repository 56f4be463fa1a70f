#version 450
// The geometry's depth from the key light (render/light_depth.h): positions only.
layout(push_constant, std430) uniform Push {
  mat4 world_to_light;
  mat4 model;
} pc;
layout(location = 0) in vec3 in_position;

void main() { gl_Position = pc.world_to_light * (pc.model * vec4(in_position, 1.0)); }
