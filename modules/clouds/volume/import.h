#pragma once
// Importers that turn outside volumes into the cloudscape NVDF pair (nvdf.h), the same files the
// baker writes, so an imported cloudscape is placed in a level like a baked one.
//
//   import_tga_slices   NVDFs shared as folders of TGA z slices (2023 talk, Nubis Voxel Clouds Pack)
//   import_vdb          OpenVDB float grids: fog volume (density) or level set (signed distance)
//   nvdfs_from_sdf      the shared last step: modeling + field NVDFs from a signed distance grid
//   save_cloudscape     writes modeling.nvdf + field.nvdf into a folder
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

struct CloudscapeVolumes {
  Volume modeling;  // kModelingFileName layout
  Volume field;     // kFieldFileName layout
};

// Defaults for modeling channels the source does not carry.
struct DeriveOptions {
  float profile_depth_m = 96.0f;  // dimensional profile reaches 1 this far inside (the baker's default)
  float profile_exponent = 1.0f;
  float detail_type = 0.5f;       // 0 wispy .. 1 billowy (2023 talk, "Detail Type")
  float density_scale = 1.0f;
};

// sdf: metres, negative inside, one value per voxel (x fastest). Values outside the field range
// (kSdfRangeMin..kSdfRangeMax) are clamped to it; the 16-bit field is rounded down (nvdf.h).
CloudscapeVolumes nvdfs_from_sdf(const std::vector<float>& sdf, glm::uvec3 size, float voxel_size,
                                 glm::vec3 bounds_min, const DeriveOptions& derive);

// ---- TGA slices ----------------------------------------------------------------------------

// Which volume axis the slice number runs along. The talk's NVDFs are 512 x 512 x 64 with Z up, so
// their slices are horizontal layers: SliceAxis::Y puts them into our Y-up layout (bake/recipe.h:
// texel (i, j, k) = world (x, y up, z)), a 512x512 image stack of 64 slices becoming 512 x 64 x 512;
// each image is a map view from above, x to the right and -z (north) at the top row.
// SliceAxis::Z keeps slices as vertical layers of constant z (the baker's own "z slice"), with the
// image's top row at the highest y.
enum class SliceAxis { Y, Z };

struct SliceImportOptions {
  SliceAxis axis = SliceAxis::Y;
  // Components (0 = R .. 3 = A) of the modeling and field slices.
  uint32_t profile_channel = 0, detail_channel = 1, density_channel = 2;
  uint32_t sdf_channel = 0;
  float sdf_min = kSdfRangeMin, sdf_max = kSdfRangeMax;  // metres that 0 and 255 stand for
  float voxel_size = 8.0f;
  // World position of the volume's min corner; default: centred on x and z with its base at y = 0,
  // where the baker's default box sits (-2048, 0, -2048)..(2048, 512, 2048).
  std::optional<glm::vec3> origin;
  DeriveOptions derive;    // used for whichever NVDF is missing
};

// The *.tga files of `dir` sorted by the number in their name (the last run of digits:
// slice_2 < slice_10). Throws naming the folder or file: missing/empty folder, a .tga without a
// number, two files with the same number.
std::vector<std::filesystem::path> numbered_slices(const std::filesystem::path& dir);

// Either folder may be empty (std::nullopt): a missing field is derived from the modeling
// profile (inside = profile > 0) by an exact distance transform, a missing modeling NVDF from the
// field's SDF with `derive` defaults. Both given: their slice counts and sizes must match.
CloudscapeVolumes import_tga_slices(const std::optional<std::filesystem::path>& modeling_dir,
                                    const std::optional<std::filesystem::path>& field_dir,
                                    const SliceImportOptions& opts);

// 'r','g','b','a' (or 0..3) -> component index; throws for anything else.
uint32_t parse_channel_letter(const std::string& s);

// ---- OpenVDB ---------------------------------------------------------------------------------

enum class VdbFilter { Box, Trilinear };

struct VdbImportOptions {
  std::string grid;               // empty: the first float grid in the file
  float voxel_size = 0.0f;        // 0: the VDB's voxel size, coarsened so no axis exceeds max_dimension
  uint32_t max_dimension = 512;   // only for the automatic voxel size
  std::optional<std::pair<glm::vec3, glm::vec3>> bounds;  // world box; default: active voxels + padding
  float padding_m = -1.0f;        // around the active voxels; <0: two of our voxels
  VdbFilter filter = VdbFilter::Box;  // box: average of up to 4^3 samples per voxel (density only)
  float iso = 0.5f;               // fog volumes: the cloud surface is where density = iso
  DeriveOptions derive;
};

// Reads a float grid: GRID_LEVEL_SET -> its signed distance (exact in the narrow band, a distance
// transform of its sign beyond it); anything else is taken as density and thresholded at `iso`
// (distance transform of the threshold, voxels next to the surface placed by the density gradient).
// Throws cumulo::Error naming the file for unreadable files, missing or non-float grids.
CloudscapeVolumes import_vdb(const std::filesystem::path& path, const VdbImportOptions& opts);

// ---- Output ----------------------------------------------------------------------------------

// Writes dir/modeling.nvdf and dir/field.nvdf (creating dir).
void save_cloudscape(const std::filesystem::path& dir, const CloudscapeVolumes& v, bool compress = true);

}  // namespace cumulo::clouds
