// The atmosphere model on the GPU (Hillaire 2020; the same integrals as engine/render/atmosphere/
// atmosphere.cpp, its CPU reference): densities, the transmittance LUT's parameterization (Bruneton 2017:
// rows linear in the distance to the horizon, columns from the ground's horizon up with u^2), psi_ms and
// the phase functions. Lengths in km.
#ifndef CUMULO_ATMOSPHERE_COMMON_GLSL
#define CUMULO_ATMOSPHERE_COMMON_GLSL
#include "shared/atmosphere_params.h"

const float kAtmPi = 3.14159265358979;

vec3 atm_extinction(AtmosphereGpuParams a, float h) {
  float hh = max(h, 0.0);
  float dr = exp(-hh / a.radii.z), dm = exp(-hh / a.radii.w);
  float dz = max(0.0, 1.0 - abs(h - a.mie.z) / (0.5 * a.mie.w));
  return a.rayleigh.rgb * dr + vec3(a.mie.y * dm) + a.ozone.rgb * dz;
}
vec3 atm_rayleigh_scattering(AtmosphereGpuParams a, float h) { return a.rayleigh.rgb * exp(-max(h, 0.0) / a.radii.z); }
float atm_mie_scattering(AtmosphereGpuParams a, float h) { return a.mie.x * exp(-max(h, 0.0) / a.radii.w); }

float atm_rayleigh_phase(float nu) { return 3.0 / (16.0 * kAtmPi) * (1.0 + nu * nu); }
float atm_mie_phase(float g, float nu) {
  float k = 3.0 / (8.0 * kAtmPi) * (1.0 - g * g) / (2.0 + g * g);
  return k * (1.0 + nu * nu) / pow(max(1.0 + g * g - 2.0 * g * nu, 1e-6), 1.5);
}

float atm_distance_to_sphere(float r, float mu, float R) {
  float disc = r * r * (mu * mu - 1.0) + R * R;
  return disc < 0.0 ? -1.0 : -r * mu + sqrt(disc);
}
bool atm_hits_ground(float r, float mu, float Rb) { return mu < 0.0 && r * r * (mu * mu - 1.0) + Rb * Rb >= 0.0; }
float atm_distance_to_ground(float r, float mu, float Rb) { return -r * mu - sqrt(max(r * r * (mu * mu - 1.0) + Rb * Rb, 0.0)); }
float atm_horizon_mu(float r, float Rb) { return -sqrt(max(0.0, 1.0 - (Rb / r) * (Rb / r))); }

// Transmittance LUT texel centre (uv) <-> (r, mu).
vec2 atm_transmittance_uv(AtmosphereGpuParams a, float r, float mu) {
  float Rb = a.radii.x, Rt = a.radii.y;
  float rho = sqrt(max(r * r - Rb * Rb, 0.0)), rho_max = sqrt(Rt * Rt - Rb * Rb);
  float mu_h = atm_horizon_mu(r, Rb);
  float u = sqrt(clamp((mu - mu_h) / (1.0 - mu_h), 0.0, 1.0));
  float v = rho / rho_max;
  // Texel centres: u, v in [0, 1] map onto [0.5, N - 0.5] texels.
  vec2 n = vec2(ATMOSPHERE_TRANSMITTANCE_W, ATMOSPHERE_TRANSMITTANCE_H);
  return (vec2(u, v) * (n - 1.0) + 0.5) / n;
}
void atm_transmittance_r_mu(AtmosphereGpuParams a, vec2 texel, out float r, out float mu) {
  float Rb = a.radii.x, Rt = a.radii.y;
  vec2 n = vec2(ATMOSPHERE_TRANSMITTANCE_W, ATMOSPHERE_TRANSMITTANCE_H);
  vec2 uv = (texel - 0.5) / (n - 1.0);
  float rho = sqrt(Rt * Rt - Rb * Rb) * uv.y;
  r = sqrt(rho * rho + Rb * Rb);
  float mu_h = atm_horizon_mu(r, Rb);
  mu = min(1.0, mu_h + uv.x * uv.x * (1.0 - mu_h) + 1e-6);
}
vec3 atm_transmittance(AtmosphereGpuParams a, sampler2D lut, float r, float mu) {
  r = clamp(r, a.radii.x, a.radii.y);
  if (atm_hits_ground(r, mu, a.radii.x)) return vec3(0.0);
  return textureLod(lut, atm_transmittance_uv(a, r, mu), 0.0).rgb;
}
vec3 atm_multiple_scattering(AtmosphereGpuParams a, sampler2D lut, float r, float mu_s) {
  vec2 uv = vec2((mu_s + 1.0) * 0.5, (r - a.radii.x) / (a.radii.y - a.radii.x));
  return textureLod(lut, clamp(uv, vec2(0.5 / ATMOSPHERE_MS_SIZE), vec2(1.0 - 0.5 / ATMOSPHERE_MS_SIZE)), 0.0).rgb;
}

// Sky-view LUT: u is the azimuth from the sun's (0..2 pi), v the elevation, dense around the horizon:
// v = 0.5 + 0.5 sign(e) sqrt(|e| / (pi / 2)).
vec2 atm_sky_view_uv(vec3 dir, vec3 sun) {
  float e = asin(clamp(dir.y, -1.0, 1.0));
  float az = atan(dir.z, dir.x) - atan(sun.z, sun.x);
  az = az - 2.0 * kAtmPi * floor(az / (2.0 * kAtmPi));
  float v = 0.5 + 0.5 * sign(e) * sqrt(abs(e) / (0.5 * kAtmPi));
  return vec2(az / (2.0 * kAtmPi), v);
}
vec3 atm_sky_view_dir(vec2 uv, vec3 sun) {
  float s = uv.y * 2.0 - 1.0;
  float e = sign(s) * s * s * 0.5 * kAtmPi;
  float az = uv.x * 2.0 * kAtmPi + atan(sun.z, sun.x);
  return vec3(cos(e) * cos(az), sin(e), cos(e) * sin(az));
}

// Aerial-perspective volume coordinates of a view distance (km) and screen uv: z = sqrt(d / D) with
// slice k's texel centre at its far end, so z = (k + 1) / N lands on texel k; nearer than slice 0's end,
// the caller blends from no haze (aerial_lookup).
vec3 atm_aerial_uvw(vec2 uv, float d_km) {
  float w = sqrt(clamp(d_km / ATMOSPHERE_AERIAL_KM, 0.0, 1.0));
  float n = float(ATMOSPHERE_AERIAL_SIZE);
  return vec3(uv, clamp(w - 0.5 / n, 0.5 / n, 1.0 - 0.5 / n));
}
// (in-scattered radiance, transmittance) from the camera to d_km along the pixel's ray.
vec4 atm_aerial_lookup(sampler3D ap, vec2 uv, float d_km) {
  vec4 v = textureLod(ap, atm_aerial_uvw(uv, d_km), 0.0);
  float first = ATMOSPHERE_AERIAL_KM / float(ATMOSPHERE_AERIAL_SIZE * ATMOSPHERE_AERIAL_SIZE);
  float f = clamp(d_km / first, 0.0, 1.0);
  return vec4(v.rgb * f, mix(1.0, v.a, f));
}

#endif
