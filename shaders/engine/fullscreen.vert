#version 450
// One triangle that covers the screen (no vertex buffer). Depth is written at the far plane, which is
// 0.0 with the engine's reversed-Z (scene/camera.h), so the sky pass can depth-test EQUAL against the
// cleared depth and fill only pixels no geometry covered.
layout(location = 0) out vec2 out_uv;

void main() {
  vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  out_uv = uv;
  gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
