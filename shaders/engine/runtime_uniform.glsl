// Lavapipe in Mesa 22.3 (Debian 12's CPU driver) compiles a compute shader again at every bind when a loop
// bound, a branch or a variable used often depends on the parameter blocks alone: it inlines the values it
// finds there (lvp_inline_uniforms) and keeps no compiled copy. The 2.5D sky, the light shafts, the aerial
// perspective and the rain were compiled again every frame, 1.5-7 ms each (docs/bench/lavapipe_sky_layer.md).
// Adding the work group's z (0 in every dispatch of ours, unknown to the compiler) keeps a value out of that
// analysis, at no cost on any device. Compute shaders only.
#ifndef CUMULO_RUNTIME_UNIFORM_GLSL
#define CUMULO_RUNTIME_UNIFORM_GLSL

float runtime_zero() { return float(gl_WorkGroupID.z); }
int runtime_int(float v) { return int(v) + int(gl_WorkGroupID.z); }
uint runtime_uint(uint v) { return v + gl_WorkGroupID.z; }
ivec2 runtime_ivec2(vec2 v) { return ivec2(v) + ivec2(gl_WorkGroupID.z); }

#endif
