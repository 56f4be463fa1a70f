#include "modules/clouds/volume/nvdf.h"

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

void check_modeling_volume(const Volume& v, std::string_view what) {
  v.channel(kDimensionalProfile, what);
  v.channel(kDetailType, what);
  v.channel(kDensityScale, what);
}

void check_field_volume(const Volume& v, std::string_view what) { v.channel(kSignedDistance, what); }

}  // namespace cumulo::clouds
