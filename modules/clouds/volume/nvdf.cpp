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
                                {"b", std::string(kDensityScale)}}),
                bounds_min);
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
