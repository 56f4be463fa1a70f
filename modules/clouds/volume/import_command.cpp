#include "modules/clouds/volume/import_command.h"

#include <cstdio>
#include <sstream>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/import_outputs.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {

namespace {

namespace fs = std::filesystem;

// "a,b,c" -> exactly n floats; throws naming the option.
std::vector<float> parse_floats(const std::string& option, const std::string& text, size_t n) {
  std::vector<float> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const float v = std::strtof(item.c_str(), &end);
    if (item.empty() || *end != '\0') fail("%s: '%s' is not a number (in '%s')", option.c_str(), item.c_str(), text.c_str());
    out.push_back(v);
  }
  if (out.size() != n) fail("%s: expected %zu comma-separated numbers, got '%s'", option.c_str(), n, text.c_str());
  return out;
}

void print_volume(const fs::path& path, const Volume& v) {
  std::printf("  %s: %ux%ux%u %s at %g m, bounds (%g, %g, %g)..(%g, %g, %g), %zu bytes on disk\n",
              path.string().c_str(), v.size.x, v.size.y, v.size.z, encoding_name(v.encoding), v.voxel_size,
              v.bounds_min.x, v.bounds_min.y, v.bounds_min.z, v.bounds_max.x, v.bounds_max.y, v.bounds_max.z,
              static_cast<size_t>(fs::file_size(path)));
}

int run_import(int argc, char** argv) {
  std::string vdb, out, modeling_dir, field_dir;
  VdbImportOptions vo;
  SliceImportOptions so;
  DeriveOptions derive;
  float voxel_size = 0.0f;
  bool no_compress = false;
  std::string filter = "box";

  ArgParser p("cumulo import",
              "Import an outside volume as a cloudscape (OUT/modeling.nvdf + OUT/field.nvdf), either an OpenVDB "
              "float grid (fog volume or level set) or NVDFs stored as folders of TGA z slices.");
  p.positional("FILE.vdb", "OpenVDB file (omit when importing TGA slices)", &vdb, false)
      .option("-o", "DIR", "output folder (required)", &out)
      .option("--grid", "NAME", "VDB: grid to read (default: the first float grid)", &vo.grid)
      .option("--voxel-size", "M", "voxel size in metres (VDB default: the VDB's, coarsened to --max-size; slices: 8)",
              &voxel_size)
      .option("--max-size", "N", "VDB: most voxels along an axis for the automatic voxel size (512)", &vo.max_dimension)
      .option("--bounds", "X0,Y0,Z0,X1,Y1,Z1", "VDB: world box to resample (default: active voxels + padding)",
              [&](const std::string& s) {
                auto f = parse_floats("--bounds", s, 6);
                vo.bounds = std::make_pair(glm::vec3(f[0], f[1], f[2]), glm::vec3(f[3], f[4], f[5]));
              })
      .option("--padding", "M", "VDB: empty margin around the active voxels (default: 2 voxels)", &vo.padding_m)
      .option("--iso", "V", "VDB fog volumes: density of the cloud surface (0.5)", &vo.iso)
      .option("--filter", "box|trilinear", "VDB fog volumes: resampling filter (box)", &filter)
      .option("--modeling", "DIR", "slices: folder of modeling TGA slices (R profile, G detail, B density)",
              &modeling_dir)
      .option("--field", "DIR", "slices: folder of field TGA slices (R signed distance)", &field_dir)
      .option("--profile-channel", "r|g|b|a", "slices: dimensional profile channel (r)",
              [&](const std::string& s) { so.profile_channel = parse_channel_letter(s); })
      .option("--detail-channel", "r|g|b|a", "slices: detail type channel (g)",
              [&](const std::string& s) { so.detail_channel = parse_channel_letter(s); })
      .option("--density-channel", "r|g|b|a", "slices: density scale channel (b)",
              [&](const std::string& s) { so.density_channel = parse_channel_letter(s); })
      .option("--sdf-channel", "r|g|b|a", "slices: signed distance channel of the field (r)",
              [&](const std::string& s) { so.sdf_channel = parse_channel_letter(s); })
      .option("--sdf-range", "MIN,MAX", "slices: metres that field values 0 and 255 stand for (-256,4096)",
              [&](const std::string& s) {
                auto f = parse_floats("--sdf-range", s, 2);
                so.sdf_min = f[0];
                so.sdf_max = f[1];
              })
      .option("--slice-axis", "y|z", "slices: volume axis the slice number runs along (y: horizontal layers, up)",
              [&](const std::string& s) {
                if (s == "y") so.axis = SliceAxis::Y;
                else if (s == "z") so.axis = SliceAxis::Z;
                else fail("--slice-axis: '%s' (expected y or z)", s.c_str());
              })
      .option("--origin", "X,Y,Z", "slices: world position of the min corner (default: centred on x/z, base at y 0)",
              [&](const std::string& s) {
                auto f = parse_floats("--origin", s, 3);
                so.origin = glm::vec3(f[0], f[1], f[2]);
              })
      .option("--profile-depth", "M", "derived profile: metres inside the surface where it reaches 1 (96)",
              &derive.profile_depth_m)
      .option("--profile-exponent", "E", "derived profile: saturate(depth / M) ^ E (1)", &derive.profile_exponent)
      .option("--detail-type", "V", "derived modeling: detail type 0 wispy..1 billowy (0.5)", &derive.detail_type)
      .option("--density-scale", "V", "derived modeling: density scale (1)", &derive.density_scale)
      .flag("--no-compress", "store the payload without zstd", &no_compress);
  if (!p.parse(argc, argv)) return 0;

  if (out.empty()) fail("cumulo import: -o DIR is required");
  const bool slices = !modeling_dir.empty() || !field_dir.empty();
  if (slices == !vdb.empty())
    fail("cumulo import: give either FILE.vdb or --modeling/--field slice folders (see cumulo import --help)");
  if (!(derive.profile_depth_m > 0.0f)) fail("--profile-depth: %g must be positive", derive.profile_depth_m);
  if (!(derive.detail_type >= 0.0f && derive.detail_type <= 1.0f)) fail("--detail-type: %g is not in 0..1", derive.detail_type);
  if (!(derive.density_scale >= 0.0f && derive.density_scale <= 1.0f))
    fail("--density-scale: %g is not in 0..1", derive.density_scale);

  Stopwatch clock;
  CloudscapeVolumes result;
  if (slices) {
    so.derive = derive;
    if (p.was_set("--voxel-size")) so.voxel_size = voxel_size;
    result = import_tga_slices(modeling_dir.empty() ? std::nullopt : std::optional<fs::path>(modeling_dir),
                               field_dir.empty() ? std::nullopt : std::optional<fs::path>(field_dir), so);
  } else {
    vo.derive = derive;
    vo.voxel_size = voxel_size;
    if (filter == "box") vo.filter = VdbFilter::Box;
    else if (filter == "trilinear") vo.filter = VdbFilter::Trilinear;
    else fail("--filter: '%s' (expected box or trilinear)", filter.c_str());
    result = import_vdb(vdb, vo);
  }
  const ImportOutputReport report = write_imported_cloudscape(out, result, !no_compress);
  std::printf("cumulo import: %s in %.2f s\n", slices ? "TGA slices" : vdb.c_str(), clock.seconds());
  for (std::string_view f : {kModelingFileName, kModelingBc1FileName, kFieldFileName, kFieldBc1FileName})
    print_volume(fs::path(out) / f, load_volume(fs::path(out) / f));
  std::printf("  field BC1 vs 16-bit: mean error %.3f m, max %.3f m, %llu values above the 16-bit field\n",
              report.field_bc1_mean_error_m, report.field_bc1_max_error_m,
              static_cast<unsigned long long>(report.field_bc1_violations));
  if (report.field_bc1_violations != 0) fail("%s: the BC1 field is not conservative", out.c_str());
  return 0;
}

}  // namespace

void register_import_command(CommandRegistry& registry) {
  registry.add({"import", "import an OpenVDB volume or TGA-slice NVDFs as a cloudscape", run_import});
}

}  // namespace cumulo::clouds
