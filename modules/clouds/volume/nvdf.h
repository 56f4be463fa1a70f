#pragma once
// NVDF conventions shared by everything that writes or reads cloudscape volumes (the baker, the
// importers, the renderer), so a baked and an imported cloudscape are interchangeable in a level.
//
// A cloudscape folder holds (2023 talk, "NVDF's"):
//   modeling.nvdf   channels dimensional_profile, detail_type, density_scale (0..1 each)
//   field.nvdf      channel sdf: signed distance, stored 0..1, decoded -256..4096 m, 16-bit (R16)
//   field_bc1.nvdf  optional: the same SDF in the conservative BC1 form (written by the baker)
// The header of each file carries size, voxel size, world bounds and channel decode ranges; a reader
// finds channels by semantic, never by position.
#include <string_view>

#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

inline constexpr std::string_view kModelingFileName = "modeling.nvdf";
inline constexpr std::string_view kFieldFileName = "field.nvdf";
inline constexpr std::string_view kFieldBc1FileName = "field_bc1.nvdf";

// An empty modeling NVDF (RGBA8; r = dimensional profile, g = detail type, b = density scale, a unused).
Volume make_modeling_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min);
// An empty field NVDF (R16 unorm, decode range kSdfRangeMin..kSdfRangeMax metres).
Volume make_field_volume(glm::uvec3 size, float voxel_size, glm::vec3 bounds_min);

// Dimensional profile from a signed distance (metres, negative inside): 0 at and outside the
// surface, rising linearly to 1 at `depth_m` inside. The talk builds the profile "from a
// signed-distance field of the cloud to ensure that we get a gradient from outside to inside".
inline float dimensional_profile_from_sdf(float sdf_m, float depth_m) {
  float t = -sdf_m / depth_m;
  return t <= 0.0f ? 0.0f : (t >= 1.0f ? 1.0f : t);
}

// Checks that a loaded volume is a usable modeling / field NVDF (has the channels by semantic);
// throws cumulo::Error naming `what`.
void check_modeling_volume(const Volume& v, std::string_view what);
void check_field_volume(const Volume& v, std::string_view what);

}  // namespace cumulo::clouds
