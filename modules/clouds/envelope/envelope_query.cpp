#include "modules/clouds/envelope/envelope_query.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "modules/clouds/envelope/envelope_bake.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds::envelope {
namespace {

float saturate(float x) { return std::clamp(x, 0.0f, 1.0f); }
float smoothstep(float e0, float e1, float x) {
  const float t = saturate((x - e0) / (e1 - e0));
  return t * t * (3.0f - 2.0f * t);
}

void require_rgba8(const Volume& v, const char* what) {
  if (v.encoding != VolumeEncoding::RGBA8)
    fail("%s: encoding %s; the envelope clouds sample RGBA8 noise", what, encoding_name(v.encoding));
}

}  // namespace

glm::vec3 envelope_scroll(glm::vec3 wind_direction, float wind_speed, float noise_tile_m, double time) {
  const float wl = glm::length(wind_direction);
  const glm::vec3 wind = wl > 0.0f ? wind_direction / wl : glm::vec3(1.0f, 0.0f, 0.0f);
  return wind * float(std::fmod(double(wind_speed) * time, double(noise_tile_m) * 64.0));
}

EnvelopeDensityQuery::EnvelopeDensityQuery(std::shared_ptr<const EnvelopeMaps> maps, Volume base_noise, Volume detail_noise)
    : maps_(std::move(maps)), base_(std::move(base_noise)), detail_(std::move(detail_noise)) {
  if (!maps_ || maps_->empty()) fail("envelope clouds: a density query needs baked maps");
  require_rgba8(base_, "envelope clouds: the base noise");
  require_rgba8(detail_, "envelope clouds: the detail noise");
}

EnvelopeDensityQuery EnvelopeDensityQuery::load(std::shared_ptr<const EnvelopeMaps> maps, const std::filesystem::path& dir) {
  const std::filesystem::path base = dir / "sky_noise_base.nvdf", detail = dir / "sky_noise_detail.nvdf";
  Volume b = load_volume(base), d = load_volume(detail);
  require_rgba8(b, base.string().c_str());
  require_rgba8(d, detail.string().c_str());
  return EnvelopeDensityQuery(std::move(maps), std::move(b), std::move(d));
}

float EnvelopeDensityQuery::density(const EnvelopeLook& look, glm::vec3 p, double time, bool detail) const {
  const EnvelopeSample s = sample_envelope(*maps_, p);
  if (s.shape.z <= 0.0f) return 0.0f;
  float profile = envelope_profile(p.y, s.shape.x, s.shape.y, s.edge_m, std::max(look.edge_m, 1e-3f),
                                   s.shape.z * std::clamp(look.coverage, 0.0f, 1.0f));
  for (const auto& [lo, hi] : look.yield_boxes) {
    const glm::vec3 outside = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
    profile *= smoothstep(0.0f, std::max(look.yield_fade_m, 1e-3f), glm::length(outside));
  }
  if (profile <= 0.0f) return 0.0f;
  const glm::vec3 q = p - envelope_scroll(look.wind_direction, look.wind_speed, look.noise_tile_m, time);
  const glm::vec3 bu = q / std::max(look.noise_tile_m, 1.0f);
  float b[4];
  for (uint32_t c = 0; c < 4; ++c) b[c] = sample_trilinear(base_, bu, c, true);
  const float worley_fbm = b[1] * 0.625f + b[2] * 0.25f + b[3] * 0.125f;
  const float wispy = saturate((b[0] - (worley_fbm - 1.0f)) / (2.0f - worley_fbm));  // Perlin-Worley (2015)
  const float composite = wispy + (worley_fbm - wispy) * s.shape.w;
  float d = saturate(composite - (1.0f - profile));
  const float erosion = std::clamp(look.detail_erosion, 0.0f, 1.0f);
  if (detail && d > 0.0f && erosion > 0.0f) {
    const glm::vec3 du = q / std::max(look.detail_tile_m, 1.0f);
    const float dfbm = sample_trilinear(detail_, du, 0, true) * 0.625f + sample_trilinear(detail_, du, 1, true) * 0.25f +
                       sample_trilinear(detail_, du, 2, true) * 0.125f;
    const float e = dfbm * erosion * 0.25f;
    d = saturate((d - e) / std::max(1.0f - e, 1e-3f));
  }
  return d * std::max(look.density, 0.0f) * std::max(look.density_scale, 0.0f);
}

}  // namespace cumulo::clouds::envelope
