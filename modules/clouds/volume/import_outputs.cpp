#include "modules/clouds/volume/import_outputs.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/bc1.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {

namespace fs = std::filesystem;

ImportOutputReport write_imported_cloudscape(const fs::path& dir, const CloudscapeVolumes& v, bool compress) {
  check_modeling_volume(v.modeling, "imported modeling volume");
  check_field_volume(v.field, "imported field volume");
  if (v.modeling.encoding != VolumeEncoding::RGBA8 || v.field.encoding != VolumeEncoding::R16 ||
      v.modeling.size != v.field.size)
    fail("write_imported_cloudscape: expected RGBA8 modeling and R16 field of one size (nvdf.h layouts)");
  const glm::uvec3 dims = v.field.size;
  Stopwatch clock;
  const size_t n = size_t(dims.x) * dims.y * dims.z;

  // Modeling BC1: the RGB encoder with the baker's weights (profile counts double: it gates density).
  const uint32_t cp = v.modeling.channel(kDimensionalProfile, ""), cd = v.modeling.channel(kDetailType, ""),
                 cs = v.modeling.channel(kDensityScale, "");
  std::vector<float> rgb(n * 3);
  const std::vector<uint8_t>& m = v.modeling.levels[0];
  for (size_t i = 0; i < n; ++i) {
    rgb[3 * i + 0] = m[4 * i + cp] / 255.0f;
    rgb[3 * i + 1] = m[4 * i + cd] / 255.0f;
    rgb[3 * i + 2] = m[4 * i + cs] / 255.0f;
  }
  Volume modeling_bc1 = Volume::create(dims, v.modeling.voxel_size, VolumeEncoding::BC1,
                                       {{"r", std::string(kDimensionalProfile)},
                                        {"g", std::string(kDetailType)},
                                        {"b", std::string(kDensityScale)}});
  modeling_bc1.bounds_min = v.modeling.bounds_min;
  modeling_bc1.bounds_max = v.modeling.bounds_max;
  modeling_bc1.levels[0] = encode_rgb_bc1(rgb, dims, glm::vec3(2.0f, 1.0f, 1.0f));
  LOG_DEBUG("import: modeling BC1 %.2f s", clock.seconds());

  // Field BC1: Hugh Malan's conservative 5:6:5 split of the (already rounded-down) 16-bit values.
  std::vector<uint16_t> values(n);
  const std::vector<uint8_t>& f = v.field.levels[0];
  for (size_t i = 0; i < n; ++i) values[i] = static_cast<uint16_t>(f[2 * i] | (f[2 * i + 1] << 8));
  Volume field_bc1 = Volume::create(dims, v.field.voxel_size, VolumeEncoding::BC1,
                                    {{"sdf_hi5", std::string(kSignedDistance), kSdfRangeMin, kSdfRangeMax}});
  field_bc1.bounds_min = v.field.bounds_min;
  field_bc1.bounds_max = v.field.bounds_max;
  field_bc1.levels[0] = encode_sdf_bc1(values, dims);
  LOG_DEBUG("import: field BC1 %.2f s", clock.seconds());
  const Bc1SdfReport check = verify_sdf_bc1(field_bc1.levels[0], values, dims);
  LOG_DEBUG("import: BC1 verify %.2f s", clock.seconds());

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) fail("%s: cannot create folder: %s", dir.string().c_str(), ec.message().c_str());
  ImportOutputReport report;
  const std::pair<std::string_view, const Volume*> outs[] = {{kModelingFileName, &v.modeling},
                                                             {kModelingBc1FileName, &modeling_bc1},
                                                             {kFieldFileName, &v.field},
                                                             {kFieldBc1FileName, &field_bc1}};
  // One set: a failed write leaves the previous import untouched (no half-replaced outputs).
  FileSet files;
  for (const auto& [name, vol] : outs) {
    std::vector<uint8_t> bytes = serialize_volume(*vol, {.compress = compress});
    files.add(dir / name, bytes);
    report.bytes_written += bytes.size();
  }
  files.commit();
  LOG_DEBUG("import: files written %.2f s", clock.seconds());
  report.field_bc1_mean_error_m = check.mean_error_m;
  report.field_bc1_max_error_m = check.max_error_m;
  report.field_bc1_violations = check.violations + check.midpoint_violations;
  return report;
}

}  // namespace cumulo::clouds
