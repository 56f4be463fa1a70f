#pragma once
// The files of an imported cloudscape: the same four the baker writes (bake/bake.h), so a level
// can point at either; the BC1 forms come from the same encoders (bc1.h).
#include <filesystem>
#include <string>

#include "modules/clouds/volume/import.h"

namespace cumulo::clouds {

struct ImportOutputReport {
  double field_bc1_mean_error_m = 0.0;  // 16-bit field minus exact BC1 decode
  double field_bc1_max_error_m = 0.0;
  uint64_t field_bc1_violations = 0;  // texels/filtered points decoding above the 16-bit value (must be 0)
  uint64_t bytes_written = 0;
};

// Writes dir/modeling.nvdf (RGBA8), modeling_bc1.nvdf, field.nvdf (R16, rounded down) and
// field_bc1.nvdf (conservative BC1) from `v` (level 0 only, like the baker's outputs).
ImportOutputReport write_imported_cloudscape(const std::filesystem::path& dir, const CloudscapeVolumes& v,
                                             bool compress = true);

}  // namespace cumulo::clouds
