// Sky gradient shared by the sky pass and the geometry pass's aerial perspective, so distant terrain
// fades into exactly the colour the sky shows behind it: zenith -> horizon gradient over elevation (the
// colours are the atmosphere's radiance straight up and at the horizon, computed on the CPU per frame:
// render/atmosphere/atmosphere.h), a ground colour below the horizon and a sun disc with a soft halo.
// (The GPU sky-view LUT of the atmosphere issue replaces the gradient's shape.)
#ifndef CUMULO_SKY_COMMON_GLSL
#define CUMULO_SKY_COMMON_GLSL
#include "shared/frame_params.h"

const vec3 kWorldUp = vec3(0.0, 1.0, 0.0);  // glTF and the level are Y-up

vec3 sky_gradient(FrameParams f, vec3 dir) {
  float e = dot(dir, kWorldUp);
  // pow 0.5 keeps the horizon band narrow and the zenith colour dominant, as in a clear sky.
  vec3 above = mix(f.sky_horizon, f.sky_zenith, pow(clamp(e, 0.0, 1.0), 0.5));
  vec3 below = mix(f.sky_horizon, f.ground_color, clamp(-e * 4.0, 0.0, 1.0));
  vec3 sky = e >= 0.0 ? above : below;
  // Forward-scattering glow around the sun (cheap Henyey-Greenstein-like lobe), stronger near the horizon.
  float mu = max(dot(dir, f.sun_direction), 0.0);
  sky += f.sun_radiance * (0.25 * pow(mu, 8.0) + 0.15 * pow(mu, 64.0)) * 0.35;
  return sky;
}

// Sun disc: angular radius about 0.53 deg / 2 (the real sun), widened a little so it survives 160x90 tests.
vec3 sun_disc(FrameParams f, vec3 dir) {
  float mu = dot(dir, f.sun_direction);
  float disc = smoothstep(0.99985, 0.99995, mu);
  return f.sun_radiance * 20.0 * disc;
}

// Exponential height fog along a ray of length dist from the camera (analytic integral of
// density * exp(-falloff * height)); returns the fraction of the surface colour that is replaced by sky.
float fog_amount(FrameParams f, vec3 dir, float dist) {
  float density = f.fog_density, falloff = max(f.fog_falloff, 1e-6);
  float h0 = f.camera_position.y;
  float dy = dir.y * dist;
  float integral = abs(dy) > 1e-3 ? (exp(-falloff * h0) - exp(-falloff * (h0 + dy))) / (falloff * dir.y)
                                  : dist * exp(-falloff * h0);
  return 1.0 - exp(-density * max(integral, 0.0));
}

#endif
