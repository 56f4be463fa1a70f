#include "modules/clouds/volume/import_command.h"

#include <cmath>
#include <cstdio>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/message.h"
#include "engine/core/time.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/import_outputs.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {

namespace {

namespace fs = std::filesystem;

// World coordinates given on the command line: the args rule (finite floats), then a box that a
// cloudscape can sit in (the recipe's limit), so origin + extent stays finite.
constexpr float kMaxWorldCoord = 1.0e6f;
std::vector<float> parse_coords(const std::string& option, const std::string& text, size_t n) {
  std::vector<float> f = parse_flag_list<float>(option, text, n);
  for (float v : f)
    if (std::abs(v) > kMaxWorldCoord)
      fail("%s: %g is outside -%g..%g metres (in %s)", option.c_str(), v, kMaxWorldCoord, kMaxWorldCoord, quote(text).c_str());
  return f;
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
      .range(0.0, 1.0e5, Open::Low)
      .option("--max-size", "N", "VDB: most voxels along an axis for the automatic voxel size (512)", &vo.max_dimension)
      .range(1, 4096)
      .option("--bounds", "X0,Y0,Z0,X1,Y1,Z1", "VDB: world box to resample (default: active voxels + padding)",
              [&](const std::string& s) {
                auto f = parse_coords("--bounds", s, 6);
                vo.bounds = std::make_pair(glm::vec3(f[0], f[1], f[2]), glm::vec3(f[3], f[4], f[5]));
                for (int a = 0; a < 3; ++a)
                  if (!(f[size_t(a) + 3] > f[size_t(a)])) fail("--bounds: max must be larger than min on every axis, got %s", quote(s).c_str());
              })
      .option("--padding", "M", "VDB: empty margin around the active voxels (default: 2 voxels)", &vo.padding_m)
      .range(0.0, kMaxWorldCoord)
      .option("--iso", "V", "VDB fog volumes: density of the cloud surface (0.5)", &vo.iso)
      .range(0.0, 1.0e6, Open::Low)
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
                auto f = parse_coords("--sdf-range", s, 2);
                if (!(f[1] > f[0])) fail("--sdf-range: expected MIN,MAX with MIN < MAX, got %s", quote(s).c_str());
                so.sdf_min = f[0];
                so.sdf_max = f[1];
              })
      .option("--slice-axis", "y|z", "slices: volume axis the slice number runs along (y: horizontal layers, up)",
              [&](const std::string& s) {
                if (s == "y") so.axis = SliceAxis::Y;
                else if (s == "z") so.axis = SliceAxis::Z;
                else fail("--slice-axis: %s (expected y or z)", quote(s, 16).c_str());
              })
      .option("--origin", "X,Y,Z", "slices: world position of the min corner (default: centred on x/z, base at y 0)",
              [&](const std::string& s) {
                auto f = parse_coords("--origin", s, 3);
                so.origin = glm::vec3(f[0], f[1], f[2]);
              })
      .option("--profile-depth", "M", "derived profile: metres inside the surface where it reaches 1 (96)",
              &derive.profile_depth_m)
      .range(0.0, 4096.0, Open::Low)  // the recipe's limits (bake/recipe.cpp)
      .option("--profile-exponent", "E", "derived profile: saturate(depth / M) ^ E (1)", &derive.profile_exponent)
      .range(0.05, 20.0)
      .option("--detail-type", "V", "derived modeling: detail type 0 wispy..1 billowy (0.5)", &derive.detail_type)
      .range(0.0, 1.0)
      .option("--density-scale", "V", "derived modeling: density scale (1)", &derive.density_scale)
      .range(0.0, 1.0)
      .flag("--no-compress", "store the payload without zstd", &no_compress);
  if (!p.parse(argc, argv)) return 0;

  if (out.empty()) fail("cumulo import: -o DIR is required");
  const bool slices = !modeling_dir.empty() || !field_dir.empty();
  if (slices == !vdb.empty())
    fail("cumulo import: give either FILE.vdb or --modeling/--field slice folders (see cumulo import --help)");

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
    else fail("--filter: %s (expected box or trilinear)", quote(filter, 16).c_str());
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
