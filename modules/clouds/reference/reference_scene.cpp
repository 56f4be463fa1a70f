#include "modules/clouds/reference/reference_scene.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "engine/core/parallel.h"
#include "engine/render/atmosphere/atmosphere.h"
#include "engine/render/sky_model.h"

namespace cumulo::clouds::render {

SkyEnvironment sky_environment(const cumulo::render::FrameSnapshot& s, uint32_t width, uint32_t height) {
  using cumulo::render::Atmosphere;
  // The weather's haze scales the Mie density of the LUTs (the real-time sky); the same here.
  const Atmosphere& base = cumulo::render::default_atmosphere();
  std::unique_ptr<Atmosphere> hazy;
  const float m = std::clamp(s.lighting.mie_scale, 0.05f, 20.0f);
  if (std::fabs(m - 1.0f) > 1e-3f) {
    cumulo::render::AtmosphereParams p = base.params();
    p.mie_scattering *= m;
    p.mie_extinction *= m;
    hazy = std::make_unique<Atmosphere>(p);
  }
  const Atmosphere& a = hazy ? *hazy : base;
  const float h = std::max(s.camera.position.y, 0.0f) * 0.001f;
  const glm::vec3 key = glm::normalize(s.sun.direction);
  const float E = a.params().solar_irradiance;
  const float night = Atmosphere::night_weight(s.sun.elevation_deg);
  SkyEnvironment env;
  env.width = width, env.height = height;
  env.texels.resize(size_t(width) * height);
  constexpr float kPi = 3.14159265f;
  parallel_for(height, [&](size_t v0, size_t v1) {
   for (size_t v = v0; v < v1; ++v) {
    const float e = (0.5f - (float(v) + 0.5f) / float(height)) * kPi;
    for (uint32_t u = 0; u < width; ++u) {
      const float az = ((float(u) + 0.5f) / float(width) - 0.5f) * 2.0f * kPi;
      const glm::vec3 dir(std::cos(e) * std::cos(az), std::sin(e), std::cos(e) * std::sin(az));
      glm::vec3 L = a.sky_radiance(h, dir, key, E);
      if (night > 0.0f) L += a.sky_radiance(h, dir, -key, E * a.moon_weight(s.sun.elevation_deg));
      L += Atmosphere::kAirglow * glm::vec3(1.0f, 1.2f, 2.0f);
      env.texels[v * width + u] = glm::vec4(L, 1.0f);
    }
   }
  });
  return env;
}

}  // namespace cumulo::clouds::render
