#include "engine/render/sky_model.h"

#include <algorithm>

namespace cumulo::render {
namespace {

float smoothstep(float a, float b, float x) {
  float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

SceneLighting stand_in_lighting(const scene::SunLight& sun) {
  SceneLighting c;
  // Day factor: civil twilight (-6 deg) to full day (+10 deg).
  float day = smoothstep(-6.0f, 10.0f, sun.elevation_deg);
  // Low sun: warm horizon. The sun's own reddening is in sun.radiance (scene::sun_transmittance).
  float low = 1.0f - smoothstep(2.0f, 25.0f, sun.elevation_deg);
  glm::vec3 night_zenith(0.004f, 0.006f, 0.015f), night_horizon(0.010f, 0.014f, 0.025f);
  // Clear-sky colours in the renderer's units (sun radiance 3 at noon, exposure 1, ACES): a saturated
  // blue zenith and a pale horizon, the look of the Burning Shores' daytime sky.
  glm::vec3 day_zenith(0.10f, 0.24f, 0.62f), day_horizon(0.55f, 0.68f, 0.85f);
  glm::vec3 sunset_horizon(0.95f, 0.55f, 0.30f);
  glm::vec3 horizon = glm::mix(day_horizon, sunset_horizon, low * 0.8f);
  c.sky_zenith = glm::mix(night_zenith, day_zenith * (1.0f - 0.35f * low), day);
  c.sky_horizon = glm::mix(night_horizon, horizon, day);
  c.ground = c.sky_horizon * 0.35f;
  c.sun_radiance = sun.radiance * kSunRadianceScale;
  c.ambient = glm::mix(0.15f, 1.0f, day);
  // About 15 % extinction over 4 km at sea level (a clear coastal day); halves every ~700 m of height.
  c.fog_density = 0.00004f;
  c.fog_falloff = 0.001f;
  return c;
}

shared::FrameParams make_frame_params(const FrameSnapshot& s, float exposure) {
  const SceneLighting& c = s.lighting;
  shared::FrameParams p{};
  p.view_proj = s.camera.view_proj;
  p.inv_view_proj = s.camera.inv_view_proj;
  p.camera_position = s.camera.position;
  p.time_s = static_cast<float>(s.sim_time);
  p.sun_direction = glm::normalize(s.sun.direction);
  p.ambient = c.ambient;
  p.sun_radiance = c.sun_radiance;
  p.exposure = exposure;
  p.sky_zenith = c.sky_zenith;
  p.fog_density = c.fog_density;
  p.sky_horizon = c.sky_horizon;
  p.fog_falloff = c.fog_falloff;
  p.ground_color = c.ground;
  float w = static_cast<float>(std::max(1u, s.width)), h = static_cast<float>(std::max(1u, s.height));
  p.viewport_size = glm::vec2(w, h);
  p.inv_viewport_size = glm::vec2(1.0f / w, 1.0f / h);
  const size_t n = std::min<size_t>(c.point_lights.size(), FRAME_MAX_POINT_LIGHTS);
  for (size_t i = 0; i < n; ++i) {
    p.point_light_pos[i] = glm::vec4(c.point_lights[i].position, std::max(c.point_lights[i].reach, 1e-3f));
    p.point_light_color[i] = glm::vec4(c.point_lights[i].color, 0.0f);
  }
  p.point_light_count = glm::uvec4(uint32_t(n), 0, 0, 0);
  return p;
}

}  // namespace cumulo::render
