#include "engine/render/sky_model.h"

#include <algorithm>

#include "engine/render/atmosphere/atmosphere.h"

namespace cumulo::render {
const Atmosphere& default_atmosphere() {
  static const Atmosphere atmosphere(load_atmosphere(default_atmosphere_file()));
  return atmosphere;
}

SceneLighting sky_lighting(const scene::SunLight& sun, float camera_altitude_m) {
  return default_atmosphere().lighting(sun, camera_altitude_m);
}

glm::vec3 key_light_direction(const FrameSnapshot& s) {
  return glm::dot(s.lighting.light_direction, s.lighting.light_direction) > 0.0f ? s.lighting.light_direction
                                                                                 : s.sun.direction;
}

shared::FrameParams make_frame_params(const FrameSnapshot& s, float exposure) {
  const SceneLighting& c = s.lighting;
  shared::FrameParams p{};
  p.view_proj = s.camera.view_proj;
  p.inv_view_proj = s.camera.inv_view_proj;
  p.camera_position = s.camera.position;
  p.time_s = static_cast<float>(s.sim_time);
  p.sun_direction = glm::normalize(key_light_direction(s));
  p.ambient = c.ambient;
  p.sun_radiance = c.sun_radiance;
  p.exposure = exposure;
  p.sky_zenith = c.sky_zenith;
  p.fog_density = c.fog_density;
  p.sky_horizon = c.sky_horizon;
  p.fog_falloff = c.fog_falloff;
  p.ground_color = c.ground;
  // Where no atmosphere gave the irradiance, the two sky colours' mean stands for it (the stand-in sky's ambient).
  const bool irradiance_known = c.sky_irradiance != glm::vec3(0.0f);
  p.sky_irradiance = glm::vec4(irradiance_known ? c.sky_irradiance : 0.5f * (c.sky_zenith + c.sky_horizon), 0.0f);
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
