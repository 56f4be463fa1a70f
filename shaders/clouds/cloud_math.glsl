// The small maths every cloud pass shares (no bindings): the voxel clouds (cloud_common.glsl), the 2.5D
// sky (sky_layer_density.glsl) and the light shafts include it.
#ifndef CUMULO_CLOUD_MATH_GLSL
#define CUMULO_CLOUD_MATH_GLSL

const float kPi = 3.14159265;
const float kEpsilon = 1e-4;

float saturate(float x) { return clamp(x, 0.0, 1.0); }
// The talk's ValueRemap / Remap: v from [a, b] to [c, d], clamped.
float value_remap(float v, float a, float b, float c, float d) { return mix(c, d, saturate((v - a) / (b - a))); }

// Henyey-Greenstein phase function (1/sr).
float henyey_greenstein(float cos_theta, float g) {
  float g2 = g * g;
  return (1.0 - g2) / (4.0 * kPi * pow(max(1.0 + g2 - 2.0 * g * cos_theta, kEpsilon), 1.5));
}

// Interleaved gradient noise (Jimenez 2014), 0..1, per pixel; `frame` animates it (golden-ratio offsets).
float pixel_hash(vec2 pixel, uint frame) {
  pixel += 5.588238 * float(frame % 64u);
  return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

#endif
