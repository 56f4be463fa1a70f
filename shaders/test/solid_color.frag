#version 460
// gpu layer test: left half push-constant color, right half its complement (checks rasterization).
layout(push_constant) uniform Push { vec4 color; float split_x; } pc;
layout(location = 0) out vec4 out_color;

void main() {
  out_color = gl_FragCoord.x < pc.split_x ? pc.color : vec4(1.0 - pc.color.rgb, 1.0);
}
