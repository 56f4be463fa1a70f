#include "engine/render/sky_model.h"

#include <algorithm>

namespace cumulo::render {
namespace {

float smoothstep(float a, float b, float x) {
  float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

SkyColors sky_colors(const SunLight& sun) {
  SkyColors c;
  // Day factor: civil twilight (-6 deg) to full day (+10 deg).
  float day = smoothstep(-6.0f, 10.0f, sun.elevation_deg);
  // Low sun: warm horizon. The tint is the sun's transmittance (already reddened by scene::sun_transmittance).
  float low = 1.0f - smoothstep(2.0f, 25.0f, sun.elevation_deg);
  glm::vec3 night_zenith(0.004f, 0.006f, 0.015f), night_horizon(0.010f, 0.014f, 0.025f);
  // Clear-sky colours in the renderer's units (sun radiance 3 at noon, exposure 1, ACES): a saturated
  // blue zenith and a pale horizon, the look of the Burning Shores' daytime sky.
  glm::vec3 day_zenith(0.10f, 0.24f, 0.62f), day_horizon(0.55f, 0.68f, 0.85f);
  glm::vec3 sunset_horizon(0.95f, 0.55f, 0.30f);
  glm::vec3 horizon = glm::mix(day_horizon, sunset_horizon, low * 0.8f);
  c.zenith = glm::mix(night_zenith, day_zenith * (1.0f - 0.35f * low), day);
  c.horizon = glm::mix(night_horizon, horizon, day);
  c.ground = c.horizon * 0.35f;
  c.sun_radiance = sun.color * sun.illuminance * 3.0f;
  c.ambient = glm::mix(0.15f, 1.0f, day);
  // About 15 % extinction over 4 km at sea level (a clear coastal day); halves every ~700 m of height.
  c.fog_density = 0.00004f;
  c.fog_falloff = 0.001f;
  return c;
}

shared::FrameParams make_frame_params(const FrameSnapshot& s, float exposure) {
  SkyColors c = sky_colors(s.sun);
  shared::FrameParams p{};
  p.view_proj = s.camera.view_proj;
  p.inv_view_proj = s.camera.inv_view_proj;
  p.camera_pos = glm::vec4(s.camera.position, static_cast<float>(s.sim_time));
  p.sun_dir = glm::vec4(glm::normalize(s.sun.direction), 1.0f);
  p.sun_color = glm::vec4(c.sun_radiance, c.ambient);
  p.sky_zenith = glm::vec4(c.zenith, c.fog_density);
  p.sky_horizon = glm::vec4(c.horizon, c.fog_falloff);
  p.ground_color = glm::vec4(c.ground, exposure);
  float w = static_cast<float>(std::max(1u, s.width)), h = static_cast<float>(std::max(1u, s.height));
  p.viewport = glm::vec4(w, h, 1.0f / w, 1.0f / h);
  return p;
}

}  // namespace cumulo::render
