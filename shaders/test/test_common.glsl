// Shared helpers for the gpu layer's tests (shaders/test/*): included by path relative to shaders/.
#ifndef TEST_COMMON_GLSL
#define TEST_COMMON_GLSL

// The value fill_pattern.comp writes at a texel: exact in float32, so tests compare for equality.
vec4 test_pattern(uvec2 p, float scale) {
  return vec4(float(p.x) / 64.0, float(p.y) / 64.0, scale, float(p.x + p.y));
}

#endif
