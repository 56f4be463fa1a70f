#include "modules/clouds/scene/density_query.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/error.h"
#include "modules/clouds/noise/noise_encode.h"
#include "modules/clouds/volume/volume_file.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds {
namespace {

float saturate(float x) { return std::clamp(x, 0.0f, 1.0f); }

}  // namespace

float coverage_presence(float coverage, float threshold) {
  return saturate(1.0f + (coverage - threshold) / float(CLOUD_COVERAGE_RAMP));
}

glm::mat4 placement_matrix(const CloudPlacement& p) {
  return glm::translate(glm::mat4(1.0f), p.position) * glm::mat4_cast(glm::normalize(p.rotation)) *
         glm::scale(glm::mat4(1.0f), glm::vec3(p.scale));
}

glm::vec3 wind_offset_asset(const CloudPlacement& p, double time) {
  const float wl = glm::length(p.wind_direction);
  const glm::vec3 wind = wl > 0.0f ? p.wind_direction / wl : glm::vec3(0.0f);
  // The time wraps at a multiple of the 100 m tile period so the float offset keeps its precision.
  const double travelled = std::fmod(double(p.wind_speed) * time, 100000.0);
  const float scale = std::max(p.scale, 1e-6f);
  return glm::inverse(glm::normalize(p.rotation)) * (wind * float(travelled / scale));
}

CloudDensityQuery::CloudDensityQuery(Volume modeling, Volume noise) : modeling_(std::move(modeling)), noise_(std::move(noise)) {
  if (is_block_encoding(modeling_.encoding) || encoding_components(modeling_.encoding) < 3)
    fail("cloud density query: the modeling NVDF must be an uncompressed 3-4 channel volume (got %s)",
         encoding_name(modeling_.encoding));
  if (encoding_components(noise_.encoding) < 4 || is_block_encoding(noise_.encoding))
    fail("cloud density query: the voxel noise must have 4 uncompressed channels (got %s)", encoding_name(noise_.encoding));
  profile_ = modeling_.channel(kDimensionalProfile, "modeling NVDF");
  type_ = modeling_.channel(kDetailType, "modeling NVDF");
  scale_ = modeling_.channel(kDensityScale, "modeling NVDF");
  coverage_ = modeling_.find_channel(kCoverageThreshold);
}

CloudDensityQuery CloudDensityQuery::load(const std::filesystem::path& folder, const std::filesystem::path& noise_file) {
  return CloudDensityQuery(load_volume(folder / "modeling.nvdf"), load_volume(noise_file));
}

float CloudDensityQuery::density(const CloudPlacement& p, glm::vec3 world, double time) const {
  const glm::vec3 asset = glm::vec3(glm::inverse(placement_matrix(p)) * glm::vec4(world, 1.0f));
  const glm::vec3 uvw = (asset - modeling_.bounds_min) / (modeling_.bounds_max - modeling_.bounds_min);
  if (glm::any(glm::lessThan(uvw, glm::vec3(0.0f))) || glm::any(glm::greaterThan(uvw, glm::vec3(1.0f)))) return 0.0f;
  float profile = sample_trilinear(modeling_, uvw, profile_, false);
  const float type = sample_trilinear(modeling_, uvw, type_, false);
  const float density_scale = sample_trilinear(modeling_, uvw, scale_, false);
  // Dissipation and coverage: the same re-ranging as cloud_common.glsl's modeling_data().
  const float dissipated = saturate(std::clamp(p.dissipation, 0.0f, 1.0f) * (1.5f + (1.0f - 1.5f) * type));
  const float coverage_threshold = coverage_ >= 0 ? sample_trilinear(modeling_, uvw, uint32_t(coverage_), false) : 0.0f;
  const float presence = coverage_presence(std::clamp(p.coverage, 0.0f, 1.0f), coverage_threshold);
  const float threshold = dissipated + (1.0f - dissipated) * (1.0f - presence);
  if (threshold > 0.0f) profile = saturate((profile - threshold) / std::max(1.0f - threshold, 1e-4f));
  if (!(profile > 0.0f)) return 0.0f;
  const glm::vec3 n = (asset - wind_offset_asset(p, time)) * 0.01f;  // the noise tiles every 100 m
  float noise[4];
  for (uint32_t c = 0; c < 4; ++c) noise[c] = sample_trilinear(noise_, n, c, true);
  return uprez_density(noise, profile, type, density_scale) * p.density;
}

}  // namespace cumulo::clouds
