#pragma once
// `cumulo bake`: recipe -> modeling and field NVDFs (2023 talk, "Voxel Cloud Modeling" and "NVDF's").
//
// Index:  BakeSettings  BakeResult  bake_recipe  bake_gpu_bytes  write_bake_outputs  write_slices  bake_report_json
//
// Stages: compose (edits per voxel, bounds-culled, all cores) -> field (exact EDT + analytic near
// the surface, 16-bit) -> modeling (profile from the field, detail type, density scale) -> BC1 field
// (conservative, verified texel by texel) -> BC1 modeling -> files.
//
// Output folder (names from modules/clouds/volume/nvdf.h):
//   modeling.nvdf      RGBA8  r profile, g detail type, b density scale, a coverage threshold  (4 B/texel: CPU devices)
//   modeling_bc1.nvdf  BC1    the first three channels                     (0.5 B/texel: GPUs)
//   coverage.nvdf      R8     coverage threshold at half resolution per axis (1/8 B/texel: the BC1 path's alpha)
//   field.nvdf         R16    sdf 0..1 <-> -256..4096 m, rounded down      (2 B/texel)
//   field_bc1.nvdf     BC1    conservative 5:6:5 split, unpack with dot(rgb, (1, 9/255, 45/65025))
//   bake_report.json   dims, bytes per output, memory totals, BC1 errors, timings
// Every volume's texel (i, j, k) is world (x, y up, z); its bounds are the recipe's world box.
//
// GPU memory choice (LAVAPIPE.md: BC6H fetches are ~75x slower on CPU devices): the talk's modeling
// NVDF is BC6H at 1 B/texel; ours is BC1 at 0.5 B/texel (three channels of smooth or piecewise
// constant data, RMSE in bake_report.json). Compressed path per 512x512x64 cloudscape: 8.389 MB
// modeling + 2.097 MB coverage + 8.389 MB field = 18.874 MB (talk: 25.166 MB; target <= 25.2 MB).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "modules/clouds/bake/compose.h"
#include "modules/clouds/bake/field.h"
#include "modules/clouds/bake/recipe.h"
#include "modules/clouds/volume/bc1.h"

namespace cumulo::clouds::bake {

struct BakeSettings {
  glm::uvec3 dims{0};      // non-zero: override the grid resolution (same bounds)
  float voxel_size = 0.0f;  // non-zero: override the recipe's voxel size
  bool verify = true;       // decode every BC1 texel and check the conservative bound
  bool show_progress = true;
};

struct BakeTimings {
  double compose = 0, field = 0, modeling = 0, bc1_field = 0, bc1_modeling = 0, verify = 0, total = 0;
};

struct BakeResult {
  BakeGrid grid;
  FieldStats field_stats;
  uint64_t edit_evaluations = 0;
  std::vector<float> field;           // metres, clamped to [-256, 4096]
  std::vector<uint16_t> field16;      // R16 (rounded down)
  std::vector<uint8_t> field_bc1;     // BC1 blocks (volume layout)
  std::vector<float> modeling;        // 3 floats per voxel: profile, detail type, density scale
  std::vector<uint8_t> modeling_bc1;  // BC1 blocks
  std::vector<float> coverage;        // coverage threshold per voxel, 0..1 (recipe.h Edit::coverage)
  // The fair-weather field (volume/nvdf.h field_fair.nvdf): R16 at field_fair_dims (half resolution), a
  // conservative SDF of the clouds below CLOUD_COVERAGE_BAND; empty when no cloud reaches the band.
  std::vector<uint16_t> field_fair16;
  glm::uvec3 field_fair_dims{0};
  Bc1SdfReport field_bc1_report;
  Bc1RgbReport modeling_bc1_report;
  double field16_max_error_m = 0.0;   // float field minus R16 decode
  BakeTimings timings;
};

// Applies the settings' overrides to a copy of the recipe and bakes it in memory.
BakeResult bake_recipe(const Recipe& recipe, const BakeSettings& settings = {});

// GPU bytes of one level in a format ("rgba8", "r16", "bc1", "bc4", "r8", ...), dims in texels.
uint64_t bake_gpu_bytes(const char* format, glm::uvec3 dims);

// Writes the five .nvdf files and bake_report.json into `dir` (created if missing); returns the
// report text.
std::string write_bake_outputs(const Recipe& recipe, const BakeResult& result, const std::filesystem::path& dir);

// Cross-sections as PNG: horizontal slices at the recipe's heights (or 3 defaults) and vertical
// slices (recipe's, or through the box centre), each as profile, colour-mapped SDF and modeling RGB.
// Returns the files written.
std::vector<std::filesystem::path> write_slices(const Recipe& recipe, const BakeResult& result,
                                                const std::filesystem::path& dir);

}  // namespace cumulo::clouds::bake
