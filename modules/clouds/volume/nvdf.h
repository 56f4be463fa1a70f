#pragma once
// NVDF conventions shared by everything that writes or reads cloudscape volumes (the baker, the
// importers, the renderer), so a baked and an imported cloudscape are interchangeable in a level.
//
// A cloudscape folder holds (2023 talk, "NVDF's"):
//   modeling.nvdf      RGBA8: dimensional_profile, detail_type, density_scale, coverage_threshold (0..1 each)
//   modeling_bc1.nvdf  the first three channels in BC1 (GPUs)
//   coverage.nvdf      R8 at half the resolution per axis (same world box): coverage_threshold, for the BC1
//                      path (BC1 has no room for a fourth channel). Optional: a folder without it (older bakes,
//                      imports) has threshold 0 everywhere, as does a modeling.nvdf without the alpha channel.
//   field.nvdf         R16, channel sdf: signed distance stored 0..1 (rounded down), decoded -256..4096 m
//   field_bc1.nvdf     the same SDF in the conservative BC1 form (bc1.h: unpack weights)
//   field_fair.nvdf    R16 at half the resolution per axis (same world box, same decode): a conservative SDF of
//                      only the clouds whose coverage threshold is below CLOUD_COVERAGE_BAND (cloud_params.h),
//                      for the march in fair weather. Optional: a bake writes it when some cloud is at or above
//                      the band; without it the march uses the field.
// Axes (bake/recipe.h): texel (i, j, k) is world (x, y up, z); bounds are the world box.
// The header of each file carries size, voxel size, world bounds and channel decode ranges; a reader
// finds channels by semantic, never by position.
#include <string_view>

#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

inline constexpr std::string_view kModelingFileName = "modeling.nvdf";
inline constexpr std::string_view kModelingBc1FileName = "modeling_bc1.nvdf";
inline constexpr std::string_view kFieldFileName = "field.nvdf";
inline constexpr std::string_view kFieldBc1FileName = "field_bc1.nvdf";
inline constexpr std::string_view kCoverageFileName = "coverage.nvdf";
inline constexpr std::string_view kFieldFairFileName = "field_fair.nvdf";

// An empty modeling NVDF (RGBA8; r = dimensional profile, g = detail type, b = density scale, a = coverage
// threshold, kCoverageThreshold; all 0).
Volume make_modeling_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min);
// The coverage NVDF of the BC1 path: R8 kCoverageThreshold at coverage_nvdf_size(modeling size), over the
// modeling's world box.
glm::uvec3 coverage_nvdf_size(glm::uvec3 modeling_size);  // half per axis, rounded up
Volume make_coverage_volume(glm::uvec3 modeling_size, float modeling_voxel_size, glm::vec3 bounds_min,
                            glm::vec3 bounds_max);
// A modeling volume's coverage thresholds downsampled to coverage_nvdf_size (box filter over each 2x2x2
// block, clamped at the edges); 0 everywhere when it has no kCoverageThreshold channel.
Volume coverage_from_modeling(const Volume& modeling);
// An empty field NVDF (R16 unorm, decode range kSdfRangeMin..kSdfRangeMax metres).
Volume make_field_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min);

// Dimensional profile from a signed distance (metres, negative inside): 0 at and outside the
// surface, saturate(-sdf / depth_m) ^ exponent below it -- the same rule as the baker's
// profile_from_field (bake/field.h), so imported and baked cloudscapes shade alike. The talk builds
// the profile "from a signed-distance field of the cloud to ensure that we get a gradient from
// outside to inside".
inline constexpr float kDefaultProfileDepth = 96.0f;  // the baker's default (bake/recipe.h ProfileParams)
float dimensional_profile_from_sdf(float sdf_m, float depth_m, float exponent = 1.0f);

// The field NVDF's 16-bit storage of a distance, rounded DOWN so a stored value never exceeds the
// true distance (a sphere tracer may step by it); clamps to kSdfRangeMin..kSdfRangeMax.
uint16_t sdf_to_unorm16_floor(float metres);

// Checks that a loaded volume is a usable modeling / field NVDF (has the channels by semantic);
// throws cumulo::Error naming `what`.
void check_modeling_volume(const Volume& v, std::string_view what);
void check_field_volume(const Volume& v, std::string_view what);

}  // namespace cumulo::clouds
