#include "modules/clouds/render/weather_lighting.h"

#include <algorithm>

namespace cumulo::clouds::render {

void apply_weather(const weather::WeatherState& w, CloudFrameInputs& in) {
  CloudSettings& s = in.settings;
  s.extinction = w.lighting.absorption;
  s.hg_forward = w.lighting.phase_forward * (1.0f - w.lighting.silver_spread);
  s.hg_backward = w.lighting.phase_backward;
  s.hg_forward_weight = w.lighting.silver_intensity;
  in.ambient_color *= w.lighting.ambient;
  for (CloudInstance& i : in.instances) {
    i.density *= w.voxel_density;
    i.coverage = w.coverage;
    i.wind_direction = w.wind_direction;
    i.wind_speed = w.wind_speed;
  }
}

float haze_mie_scale(float haze) { return std::max(0.25f, 1.0f + (std::clamp(haze, 0.0f, 1.0f) - 0.1f) * 10.0f); }

}  // namespace cumulo::clouds::render
