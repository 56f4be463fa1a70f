#version 450
// Render-graph test: temporal accumulation through a history pair: current = previous (if valid) + add.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D previous;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D current;
layout(push_constant) uniform Push { float valid; float add; } pc;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(current)))) return;
  float v = (pc.valid > 0.5 ? imageLoad(previous, p).r : 0.0) + pc.add;
  imageStore(current, p, vec4(v));
}
