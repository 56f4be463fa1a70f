#pragma once
// A grown cloud: what the cloud-formation solver leaves, cropped to the cloud and in the asset's game
// metres, with the fields the attribute rules read (grown_attributes.h).
//
// Index:  GrownCloud  GrowReport  grow_cloud  save_grown / load_grown  write_grow_outputs
//
// Local frame: x and z centred on the solver's box, y = 0 at the cloud's base (its lowest cell of cloud
// water above the iso-surface): a recipe's "position" is where the base centre goes.
//
// File (the project's volume format, modules/clouds/volume/volume_file.h): grown.nvdf, RGBA16 unorm,
// channels cloud_water (kg/kg), condensation (kg/kg/s, > 0 condensing), vertical_velocity (m/s) and
// growth (d(cloud water)/dt at a fixed point, kg/kg/s), each with its decode range; bounds in local
// game metres.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/bake/grow/grow_spec.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo {
class Progress;
}

namespace cumulo::clouds::grow {

inline constexpr std::string_view kCloudWater = "cloud_water";
inline constexpr std::string_view kCondensation = "condensation";
inline constexpr std::string_view kVerticalVelocity = "vertical_velocity";
inline constexpr std::string_view kGrowth = "cloud_water_growth";

struct GrownCloud {
  glm::uvec3 dims{0};
  float cell = 16.0f;        // game metres
  glm::vec3 origin{0.0f};    // local position of cell (0, 0, 0)'s centre
  float iso = 0.05e-3f;      // kg/kg: the cloud's surface
  std::vector<float> cloud_water, condensation, vertical_velocity, growth;
  size_t count() const { return size_t(dims.x) * dims.y * dims.z; }
  size_t index(uint32_t x, uint32_t y, uint32_t z) const { return x + size_t(dims.x) * (y + size_t(dims.y) * z); }
  glm::vec3 bounds_min() const { return origin - 0.5f * cell; }
  glm::vec3 bounds_max() const { return origin + (glm::vec3(dims) - 0.5f) * cell; }
};

struct GrowReport {
  int steps = 0;
  double physical_seconds = 0, wall_seconds = 0;
  unsigned threads = 0;
  WaterBudget water;
  double total_water_drift = 0;  // advection residual over the initial water
  float cloud_base_m = 0, cloud_top_m = 0;  // game metres above the solver's floor
  float condensation_level_m = 0;           // the floor air's LCL, game metres
  glm::vec3 cloud_size{0.0f};               // game metres
  uint64_t cloud_cells = 0;
  uint64_t speckle_cells_removed = 0;  // cells of pieces too small to be part of the cloud
  float max_cloud_water = 0, max_updraft = 0;
  int mean_pressure_iterations = 0;
};

// Runs the solver for the spec's steps (a progress line with an ETA when `progress`) and crops the
// result. Fails naming the spec when no cloud water reached the iso-surface.
GrownCloud grow_cloud(const GrowSpec& spec, GrowReport* report, Progress* progress);

Volume grown_to_volume(const GrownCloud& g);
GrownCloud grown_from_volume(const Volume& v, const std::string& what);
void save_grown(const std::filesystem::path& path, const GrownCloud& g);
GrownCloud load_grown(const std::filesystem::path& path);

// DIR/grown.nvdf, DIR/grown.vdb (OpenVDB fog volume "density", when built with OpenVDB),
// DIR/grown_section.png (vertical and horizontal cross-sections), DIR/grow_report.json (with "key").
// All or nothing: a failure leaves DIR's previous files. Returns the report text.
std::string write_grow_outputs(const GrowSpec& spec, const GrownCloud& g, const GrowReport& r,
                               const std::filesystem::path& dir);

// The key recorded in DIR/grow_report.json, or "" when there is none.
std::string recorded_grow_key(const std::filesystem::path& dir);

// Writes a fog volume (cloud water / iso, clamped to 0..1) as OpenVDB; false when OpenVDB is not built in.
bool write_grown_vdb(const std::filesystem::path& path, const GrownCloud& g);

}  // namespace cumulo::clouds::grow
