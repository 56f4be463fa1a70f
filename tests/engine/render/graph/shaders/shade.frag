#version 450
// Render-graph test: a fragment pass sampling a compute-written image: out = 3 * field + 1.
layout(set = 0, binding = 0) uniform sampler2D field;
layout(location = 0) out vec4 color;
void main() { color = vec4(3.0 * texelFetch(field, ivec2(gl_FragCoord.xy), 0).r + 1.0); }
