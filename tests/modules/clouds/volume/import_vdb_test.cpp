// OpenVDB import on VDB files this test writes with OpenVDB itself: a sphere level set and the
// same sphere as a fog volume, checked against the analytic distance at every voxel.
#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <cstdio>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/nvdf.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

constexpr float kRadius = 40.0f;
const glm::vec3 kCentre{10.0f, -20.0f, 130.0f};
constexpr float kHalfWidth = 3.0f;  // narrow band, in VDB voxels of 1 m

class VdbImport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    openvdb::initialize();
    dir_ = cumulo::test::unique_temp_path("cumulo_volume_vdb_test");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    auto ls = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        kRadius, openvdb::Vec3f(kCentre.x, kCentre.y, kCentre.z), 1.0f, kHalfWidth);
    ls->setName("surface");
    auto vel = openvdb::Vec3SGrid::create();
    vel->setName("vel");
    openvdb::io::File(level_set_path().string()).write({vel, ls});
    auto fog = ls->deepCopy();
    openvdb::tools::sdfToFogVolume(*fog);  // 0 outside, 1 inside, -sdf / band across the band
    fog->setName("density");
    openvdb::io::File(fog_path().string()).write({fog});
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path level_set_path() { return dir_ / "sphere_ls.vdb"; }
  static fs::path fog_path() { return dir_ / "sphere_fog.vdb"; }

  // Compares the field's SDF with |p - c| - surface_radius at every voxel centre.
  static void expect_sphere(const CloudscapeVolumes& v, float surface_radius, float band_tol, float far_tol,
                            float band) {
    const Volume& f = v.field;
    const uint32_t cf = f.channel(kSignedDistance, "field");
    double sum_err = 0.0, band_sum = 0.0;
    float band_max = 0.0f;
    int band_n = 0;
    float max_err = 0.0f;
    for (uint32_t z = 0; z < f.size.z; ++z)
      for (uint32_t y = 0; y < f.size.y; ++y)
        for (uint32_t x = 0; x < f.size.x; ++x) {
          const glm::vec3 p = f.bounds_min + (glm::vec3(x, y, z) + 0.5f) * f.voxel_size;
          const float want = glm::length(p - kCentre) - surface_radius;
          const float got = f.decoded(x, y, z, cf);
          const float err = std::fabs(got - want);
          sum_err += err;
          max_err = std::max(max_err, err);
          if (std::fabs(want) < band) band_sum += err, band_max = std::max(band_max, err), ++band_n;
          ASSERT_LE(err, std::fabs(want) < band ? band_tol : far_tol) << "voxel " << x << "," << y << "," << z
                                                                      << " want " << want << " got " << got;
        }
    EXPECT_LT(sum_err / double(f.size.x * f.size.y * f.size.z), 0.5 * far_tol);
    RecordProperty("max_sdf_error_m", std::to_string(max_err));
    std::printf("sdf error: all voxels mean %.3f max %.3f m; within %.1f m of the surface (%d voxels) mean %.3f max %.3f m\n",
                sum_err / double(f.size.x * f.size.y * f.size.z), max_err, band, band_n, band_n ? band_sum / band_n : 0.0,
                band_max);
  }
  static fs::path dir_;
};
fs::path VdbImport::dir_;

TEST_F(VdbImport, LevelSetGivesSignedDistance) {
  VdbImportOptions o;
  o.voxel_size = 4.0f;
  o.derive.profile_depth_m = 20.0f;
  CloudscapeVolumes v = import_vdb(level_set_path(), o);  // picks "surface": the first float grid
  // Box: active band (radius + 3 m, voxel-rounded) + 2 voxels of padding on each side.
  EXPECT_NEAR(v.field.bounds_min.x, kCentre.x - kRadius - kHalfWidth - 0.5f - 8.0f, 1.01f);
  EXPECT_EQ(v.field.size, v.modeling.size);
  EXPECT_EQ(v.field.size.x, 26u);  // ceil((87 + 16) / 4)
  // Exact (trilinear) inside the narrow band; beyond it the distance transform's accuracy (the
  // surface placed halfway between voxel centres: within about one of our voxels).
  // The level set's values are used where trilinear sampling is exact: band - sqrt(3) VDB voxels.
  expect_sphere(v, kRadius, 0.15f, 4.0f, kHalfWidth - 1.75f);
  // Profile: 1 deep inside, 0 outside, a ramp of 20 m below the surface.
  const Volume& m = v.modeling;
  const uint32_t cp = m.channel(kDimensionalProfile, "m"), cd = m.channel(kDetailType, "m"),
                 cs = m.channel(kDensityScale, "m");
  const glm::uvec3 c = glm::uvec3((kCentre - m.bounds_min) / m.voxel_size);
  EXPECT_FLOAT_EQ(m.texel(c.x, c.y, c.z, cp), 1.0f);
  EXPECT_FLOAT_EQ(m.texel(0, 0, 0, cp), 0.0f);
  EXPECT_NEAR(m.texel(c.x, c.y, c.z, cd), 0.5f, 1.0f / 255.0f);
  EXPECT_FLOAT_EQ(m.texel(c.x, c.y, c.z, cs), 1.0f);
  EXPECT_FLOAT_EQ(m.texel(0, 0, 0, cs), 0.0f);
}

TEST_F(VdbImport, FogVolumeIsThresholdedAtIso) {
  VdbImportOptions o;
  o.voxel_size = 2.0f;
  CloudscapeVolumes v = import_vdb(fog_path(), o);
  // sdfToFogVolume maps sdf 0 -> 0 and sdf -band -> 1, so density 0.5 lies 1.5 m inside.
  // Within a voxel of the surface the density gradient places it to a fraction of a voxel
  // (measured: mean 0.16 m, max 0.60 m at 2 m voxels; 0.53 / 1.04 m without that refinement);
  // beyond, the distance transform is good to about a voxel.
  expect_sphere(v, kRadius - 0.5f * kHalfWidth, 0.65f, 2.0f, 1.0f);
  const glm::uvec3 c = glm::uvec3((kCentre - v.modeling.bounds_min) / v.modeling.voxel_size);
  // Default 96 m profile depth; the distance transform is good to about a voxel (2 m).
  EXPECT_NEAR(v.modeling.texel(c.x, c.y, c.z, 0), 38.5f / 96.0f, 2.0f / 96.0f);
}

TEST_F(VdbImport, AutomaticVoxelSizeAndBounds) {
  VdbImportOptions o;
  o.max_dimension = 32;
  CloudscapeVolumes v = import_vdb(fog_path(), o);
  // The fog's active voxels are the interior (79 m across) -> 79 / 32 m voxels, plus two voxels
  // of padding on each side.
  EXPECT_NEAR(v.field.voxel_size, 79.0f / 32.0f, 0.01f);
  EXPECT_LE(v.field.size.x, 36u);
  o.voxel_size = 5.0f;
  o.bounds = std::make_pair(glm::vec3(-40, -70, 80), glm::vec3(60, 30, 180));
  v = import_vdb(fog_path(), o);
  EXPECT_EQ(v.field.size, glm::uvec3(20, 20, 20));
  EXPECT_EQ(v.field.bounds_min, glm::vec3(-40, -70, 80));
}

TEST_F(VdbImport, ErrorsNameTheFileAndGrid) {
  auto error_of = [](const fs::path& p, const std::string& grid) {
    try {
      VdbImportOptions o;
      o.grid = grid;
      o.voxel_size = 8.0f;
      import_vdb(p, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::string msg = error_of(level_set_path(), "vel");
  EXPECT_NE(msg.find("sphere_ls.vdb: grid 'vel' holds vec3s values, not float"), std::string::npos) << msg;
  msg = error_of(level_set_path(), "nope");
  EXPECT_NE(msg.find("sphere_ls.vdb: no grid named 'nope' (grids: "), std::string::npos) << msg;
  EXPECT_NE(msg.find("'vel' (vec3s)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'surface' (float)"), std::string::npos) << msg;
  msg = error_of(dir_ / "missing.vdb", "");
  EXPECT_NE(msg.find("missing.vdb: cannot read VDB file"), std::string::npos) << msg;
  write_file_atomic(dir_ / "garbage.vdb", std::string("this is not a vdb file at all"));
  msg = error_of(dir_ / "garbage.vdb", "");
  EXPECT_NE(msg.find("garbage.vdb: cannot read VDB file"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("IoError"), std::string::npos) << msg;  // library prefixes are translated
}

// A cut VDB used to import with exit 0 and garbage past the cut (the active voxel count lives in the
// intact part), and a 300-byte cut made OpenVDB allocate 18 GB. Every cut is refused, quickly.
TEST_F(VdbImport, TruncatedFilesAreRefusedAtEveryCut) {
  const std::vector<uint8_t> whole = read_file_bytes(fog_path());
  ASSERT_GT(whole.size(), 1000u);
  std::vector<size_t> cuts = {whole.size() / 2, 300, whole.size() - 1, 8, 60};
  for (size_t c = 100; c < whole.size(); c += whole.size() / 17) cuts.push_back(c);
  for (size_t cut : cuts) {
    const fs::path p = dir_ / "cut.vdb";
    write_file_atomic(p, std::span<const uint8_t>(whole.data(), cut));
    try {
      VdbImportOptions o;
      o.voxel_size = 8.0f;
      import_vdb(p, o);
      ADD_FAILURE() << "a VDB cut at " << cut << " of " << whole.size() << " bytes was accepted";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("cut.vdb: "), std::string::npos) << msg;
      EXPECT_NE(msg.find("truncated"), std::string::npos) << "cut at " << cut << ": " << msg;
    }
  }
}

// The grid's data overwritten with 0xFF, container intact: uncompressed leaves then hold NaN
// floats, which imported with exit 0 as garbage; voxel values follow the outside-number rule.
TEST_F(VdbImport, CorruptGridDataIsRefused) {
  auto fog = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(kRadius, openvdb::Vec3f(kCentre.x, kCentre.y, kCentre.z),
                                                                       1.0f, kHalfWidth);
  openvdb::tools::sdfToFogVolume(*fog);
  fog->setName("density");
  const fs::path raw = dir_ / "raw.vdb";
  openvdb::io::File out(raw.string());
  out.setCompression(openvdb::io::COMPRESS_NONE);
  out.write({fog});
  out.close();
  std::vector<uint8_t> bytes = read_file_bytes(raw);
  for (size_t i = bytes.size() / 3; i < bytes.size(); ++i) bytes[i] = 0xFF;
  const fs::path p = dir_ / "corrupt.vdb";
  write_file_atomic(p, bytes);
  try {
    VdbImportOptions o;
    o.voxel_size = 8.0f;
    import_vdb(p, o);
    ADD_FAILURE() << "a corrupt VDB was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("corrupt.vdb: "), std::string::npos) << msg;
    EXPECT_TRUE(msg.find("not a finite number") != std::string::npos || msg.find("corrupt") != std::string::npos) << msg;
  }
}

TEST_F(VdbImport, GridLargerThanTheMemoryBudgetIsRefused) {
  VdbImportOptions o;
  o.voxel_size = 0.05f;  // 4096 voxels per axis over the sphere's 82 m box
  o.max_dimension = 4096;
  try {
    import_vdb(fog_path(), o);
    FAIL() << "accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("sphere_fog.vdb: importing as"), std::string::npos) << msg;
    EXPECT_NE(msg.find("memory budget"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace cumulo::clouds
