#pragma once
// Cloud density at a point on the CPU (issue 9: gameplay asks where the cloud is: wing-tip streamers,
// audio, whether the player is inside the storm). The same field the GPU marches at a distance: the
// modeling NVDF (trilinear, clamped to the box), dissipation and coverage, the wind-scrolled voxel noise (trilinear,
// repeating, mip 0) and the up-rez without the near-camera details, times the instance's density: what
// cloud_common.glsl's sample_density(.., details = false).full returns at noise mip 0. A test compares the
// two at many points (tests/modules/clouds/render).
//
//   CloudDensityQuery q = CloudDensityQuery::load(cloudscape_folder, noise_file);
//   float d = q.density(instance, player_position, sim_time);   // 0 outside cloud
#include <filesystem>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

// A placed cloudscape as the renderer sees it (CloudInstance without the GPU asset).
struct CloudPlacement {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  float scale = 1.0f;
  float density = 1.0f;
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;
  float dissipation = 0.0f;
  // The weather's coverage 0..1 (frame/cloud_extraction.h): cloud whose coverage threshold is above it thins and goes
  // (coverage_presence). 1: every cloud present (no weather).
  float coverage = 1.0f;
};

// The presence 0..1 of cloud with coverage threshold `threshold` at the weather's `coverage`: 1 at
// coverage >= threshold, 0 at coverage <= threshold - CLOUD_COVERAGE_RAMP (shaders/shared/cloud_params.h), linear
// between; cloud_common.glsl's coverage_presence.
float coverage_presence(float coverage, float threshold);

// The instance transform (world = position + rotation * (scale * asset)) and the noise scroll in asset
// metres after `time` seconds: the one definition the renderer and the query share.
glm::mat4 placement_matrix(const CloudPlacement& p);
glm::vec3 wind_offset_asset(const CloudPlacement& p, double time);

class CloudDensityQuery {
 public:
  // `modeling`: the asset's modeling NVDF (profile, detail type, density scale and, when it has the channel, the
  // coverage threshold, else 0; unorm encodings);
  // `noise`: the 4-channel voxel noise.
  CloudDensityQuery(Volume modeling, Volume noise);
  static CloudDensityQuery load(const std::filesystem::path& cloudscape_folder, const std::filesystem::path& noise_file);

  float density(const CloudPlacement& p, glm::vec3 world, double time) const;
  glm::vec3 bounds_min() const { return modeling_.bounds_min; }
  glm::vec3 bounds_max() const { return modeling_.bounds_max; }

 private:
  Volume modeling_, noise_;
  uint32_t profile_ = 0, type_ = 1, scale_ = 2;  // modeling components
  int coverage_ = -1;                             // the coverage threshold's component, -1: none (threshold 0)
};

}  // namespace cumulo::clouds
