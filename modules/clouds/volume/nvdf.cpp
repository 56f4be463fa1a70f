#include "modules/clouds/volume/nvdf.h"

#include <cmath>

#include "engine/core/error.h"

namespace cumulo::clouds {

namespace {
Volume placed(Volume v, glm::vec3 bounds_min) {
  v.bounds_min = bounds_min;
  v.bounds_max = bounds_min + glm::vec3(v.size) * v.voxel_size;
  return v;
}
}  // namespace

Volume make_modeling_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min) {
  return placed(Volume::create(size, voxel_size, VolumeEncoding::RGBA8,
                               {{"r", std::string(kDimensionalProfile)},
                                {"g", std::string(kDetailType)},
                                {"b", std::string(kDensityScale)},
                                {"a", std::string(kCoverageThreshold)}}),
                bounds_min);
}

glm::uvec3 coverage_nvdf_size(glm::uvec3 s) { return glm::max((s + 1u) / 2u, glm::uvec3(1)); }

Volume make_coverage_volume(glm::uvec3 modeling_size, float modeling_voxel_size, glm::vec3 bounds_min,
                            glm::vec3 bounds_max) {
  const glm::uvec3 size = coverage_nvdf_size(modeling_size);
  Volume v = Volume::create(size, 2.0f * modeling_voxel_size, VolumeEncoding::R8, {{"r", std::string(kCoverageThreshold)}});
  v.bounds_min = bounds_min;
  v.bounds_max = bounds_max;
  return v;
}

Volume coverage_from_modeling(const Volume& m) {
  Volume out = make_coverage_volume(m.size, m.voxel_size, m.bounds_min, m.bounds_max);
  const int c = m.find_channel(kCoverageThreshold);
  if (c < 0 || is_block_encoding(m.encoding)) return out;
  const glm::uvec3 s = out.size;
  for (uint32_t z = 0; z < s.z; ++z)
    for (uint32_t y = 0; y < s.y; ++y)
      for (uint32_t x = 0; x < s.x; ++x) {
        float sum = 0.0f;
        for (uint32_t k = 0; k < 8; ++k) {
          const glm::uvec3 p = glm::min(glm::uvec3(2 * x + (k & 1), 2 * y + ((k >> 1) & 1), 2 * z + (k >> 2)), m.size - 1u);
          sum += m.texel(p.x, p.y, p.z, uint32_t(c));
        }
        out.set_texel(x, y, z, 0, sum / 8.0f);
      }
  return out;
}

Volume make_field_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min) {
  return placed(Volume::create(size, voxel_size, VolumeEncoding::R16,
                               {{"r", std::string(kSignedDistance), kSdfRangeMin, kSdfRangeMax}}),
                bounds_min);
}

float dimensional_profile_from_sdf(float sdf_m, float depth_m, float exponent) {
  float t = -sdf_m / depth_m;
  t = t <= 0.0f ? 0.0f : (t >= 1.0f ? 1.0f : t);  // also maps NaN to 0
  return exponent == 1.0f ? t : std::pow(t, exponent);
}

uint16_t sdf_to_unorm16_floor(float metres) {
  double v = (double(metres) - kSdfRangeMin) / (double(kSdfRangeMax) - kSdfRangeMin);
  v = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
  return static_cast<uint16_t>(v * 65535.0);  // truncation = floor for v >= 0
}

void check_modeling_volume(const Volume& v, std::string_view what) {
  v.channel(kDimensionalProfile, what);
  v.channel(kDetailType, what);
  v.channel(kDensityScale, what);
}

void check_field_volume(const Volume& v, std::string_view what) { v.channel(kSignedDistance, what); }

}  // namespace cumulo::clouds
