// `cumulo import` end to end on TGA slices the test writes: the four files a bake writes, loadable,
// with a conservative BC1 field; command-line errors.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/volume/import_command.h"
#include "modules/clouds/volume/import_outputs.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/tga.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

int run_import(std::vector<std::string> args) {
  CommandRegistry registry;
  register_import_command(registry);
  const Command* c = registry.find("import");
  EXPECT_NE(c, nullptr);
  args.insert(args.begin(), "import");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return c->run(int(argv.size()), argv.data());
}

// A 32 x 32 x 8 field stack holding the distance to a sphere (radius 40 m at 4 m voxels), encoded
// in the talk's -256..4096 m range.
fs::path write_sphere_field(const fs::path& dir) {
  fs::create_directories(dir);
  for (uint32_t k = 0; k < 8; ++k) {
    Rgba8Image img{32, 32, std::vector<uint8_t>(32 * 32 * 4, 255)};
    for (uint32_t r = 0; r < 32; ++r)
      for (uint32_t x = 0; x < 32; ++x) {
        const glm::vec3 p = (glm::vec3(x, k, r) + 0.5f) * 4.0f - glm::vec3(64, 16, 64);
        const float d = glm::length(p) - 40.0f;
        img.rgba[(r * 32 + x) * 4] = uint8_t(std::lround((d + 256.0f) / 4352.0f * 255.0f));
      }
    write_file_atomic(dir / ("sdf." + std::to_string(k) + ".tga"), encode_tga(img, true));
  }
  return dir;
}

TEST(ImportCommand, SlicesToTheBakersFourFiles) {
  const fs::path root = cumulo::test::unique_temp_path("cumulo_volume_import_command");
  fs::remove_all(root);
  const fs::path field = write_sphere_field(root / "field");
  ASSERT_EQ(run_import({"--field", field.string(), "-o", (root / "out").string(), "--voxel-size", "4"}), 0);
  Volume m = load_volume(root / "out" / kModelingFileName);
  Volume mb = load_volume(root / "out" / kModelingBc1FileName);
  Volume f = load_volume(root / "out" / kFieldFileName);
  Volume fb = load_volume(root / "out" / kFieldBc1FileName);
  check_modeling_volume(m, "m");
  check_modeling_volume(mb, "mb");
  check_field_volume(f, "f");
  check_field_volume(fb, "fb");
  EXPECT_EQ(m.size, glm::uvec3(32, 8, 32));
  EXPECT_EQ(mb.encoding, VolumeEncoding::BC1);
  EXPECT_EQ(fb.encoding, VolumeEncoding::BC1);
  EXPECT_EQ(fb.bounds_min, f.bounds_min);
  EXPECT_EQ(f.bounds_min, glm::vec3(-64, 0, -64));
  // Profile at the sphere's centre row: SDF about -40 + 16 -> profile (40 - 16) / 96 > 0; far corner 0.
  EXPECT_GT(m.texel(16, 4, 16, 0), 0.2f);
  EXPECT_EQ(m.texel(0, 0, 0, 0), 0.0f);
  // BC1 profile close to RGBA8's.
  EXPECT_NEAR(mb.texel(16, 4, 16, 0), m.texel(16, 4, 16, 0), 0.05f);
  fs::remove_all(root);
}

TEST(ImportCommand, WriterReportsConservativeBc1) {
  const fs::path root = cumulo::test::unique_temp_path("cumulo_volume_import_writer");
  fs::remove_all(root);
  write_sphere_field(root / "field");
  SliceImportOptions o;
  o.voxel_size = 4.0f;
  CloudscapeVolumes v = import_tga_slices(std::nullopt, root / "field", o);
  ImportOutputReport r = write_imported_cloudscape(root / "out", v);
  EXPECT_EQ(r.field_bc1_violations, 0u);
  EXPECT_LT(r.field_bc1_max_error_m, 17.1f);  // at most one 8-bit source step
  EXPECT_GT(r.bytes_written, 0u);
  fs::remove_all(root);
}

TEST(ImportCommand, FailedImportLeavesThePreviousSetUntouched) {
  const fs::path root = cumulo::test::unique_temp_path("cumulo_volume_import_set");
  fs::remove_all(root);
  const fs::path field = write_sphere_field(root / "field"), out = root / "out";
  ASSERT_EQ(run_import({"--field", field.string(), "-o", out.string(), "--voxel-size", "4"}), 0);
  const std::string_view names[] = {kModelingFileName, kModelingBc1FileName, kFieldFileName};
  std::vector<std::vector<uint8_t>> before;
  for (std::string_view n : names) before.push_back(read_file_bytes(out / n));
  // The last file of the set cannot be written: its path is a folder now.
  fs::remove(out / kFieldBc1FileName);
  fs::create_directories(out / kFieldBc1FileName);
  EXPECT_THROW(run_import({"--field", field.string(), "-o", out.string(), "--voxel-size", "8"}), Error);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(read_file_bytes(out / names[i]), before[i]) << names[i];
  for (const auto& e : fs::directory_iterator(out)) EXPECT_NE(e.path().extension(), ".tmp") << e.path() << " left behind";
  fs::remove_all(root);
}

// `n` copies of one TGA as sdf.0.tga .. sdf.<n-1>.tga (plain writes: an fsync each would make the tests slow).
void write_slices(const fs::path& dir, const std::vector<uint8_t>& bytes, int n) {
  for (int k = 0; k < n; ++k)
    std::ofstream(dir / ("sdf." + std::to_string(k) + ".tga"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

TEST(ImportCommand, SliceStackOverTheMemoryBudgetIsRefusedBeforeDecoding) {
  // 64 slices of 1024 x 1024 (one RLE colour each, 40 KB a file): 3.8 GB of pixels and volumes before any volume work,
  // against a budget of 64 MB.
  const fs::path root = cumulo::test::unique_temp_path("cumulo_volume_import_budget");
  fs::remove_all(root);
  fs::create_directories(root / "field");
  Rgba8Image slice;
  slice.width = slice.height = 1024;
  slice.rgba.assign(size_t(1024) * 1024 * 4, 128);
  const std::vector<uint8_t> bytes = encode_tga(slice, true);
  write_slices(root / "field", bytes, 64);
  const char* old = std::getenv("CUMULO_MEMORY_BUDGET_MB");
  const std::string saved = old ? old : "";
  setenv("CUMULO_MEMORY_BUDGET_MB", "64", 1);
  try {
    run_import({"--field", (root / "field").string(), "-o", (root / "out").string()});
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("field: 64 TGA slices of up to 1048576 pixels"), std::string::npos) << msg;
    EXPECT_NE(msg.find("memory budget"), std::string::npos) << msg;
  }
  if (old) setenv("CUMULO_MEMORY_BUDGET_MB", saved.c_str(), 1);
  else unsetenv("CUMULO_MEMORY_BUDGET_MB");
  fs::remove_all(root);
}

// A slice that is no TGA (a text file named .tga read as a 760-megapixel image) is named by the error, before its
// made-up size reaches the budget; so is a slice whose header claims more pixels than the file holds.
TEST(ImportCommand, ASliceThatIsNoTgaIsNamed) {
  const fs::path root = cumulo::test::unique_temp_path("cumulo_volume_import_not_tga");
  fs::remove_all(root);
  fs::create_directories(root / "field");
  Rgba8Image slice;
  slice.width = slice.height = 8;
  slice.rgba.assign(8 * 8 * 4, 200);
  const std::vector<uint8_t> bytes = encode_tga(slice, false);
  write_slices(root / "field", bytes, 4);
  std::ofstream(root / "field" / "sdf.2.tga") << "This is a text file, not an image: it only has a .tga name.\n";
  auto error_of = [&] {
    try {
      run_import({"--field", (root / "field").string(), "-o", (root / "out").string(), "--voxel-size", "8"});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::string msg = error_of();
  EXPECT_NE(msg.find("sdf.2.tga: "), std::string::npos) << msg;
  EXPECT_EQ(msg.find("memory budget"), std::string::npos) << msg;
  // A header claiming 4096 x 4096 over 18 bytes: named as truncated, not budgeted as 64 MB of pixels.
  std::vector<uint8_t> header(18, 0);
  header[2] = 2, header[13] = 0x10, header[15] = 0x10, header[16] = 32;
  std::ofstream(root / "field" / "sdf.2.tga", std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(header.data()), std::streamsize(header.size()));
  msg = error_of();
  EXPECT_NE(msg.find("sdf.2.tga: truncated TGA"), std::string::npos) << msg;
  fs::remove_all(root);
}

TEST(ImportCommand, CommandLineErrors) {
  auto error_of = [](std::vector<std::string> args) {
    try {
      run_import(std::move(args));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(error_of({"x.vdb"}).find("-o DIR is required"), std::string::npos);
  EXPECT_NE(error_of({"-o", "/tmp/x"}).find("give either FILE.vdb or --modeling/--field"), std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "--modeling", "d", "-o", "/tmp/x"}).find("give either"), std::string::npos);
  EXPECT_NE(error_of({"--field", "d", "-o", "/tmp/x", "--sdf-range", "1,b"}).find("--sdf-range: expected a number, got \"b\""),
            std::string::npos);
  // Outside numbers on the command line: finite and in range, or refused naming the flag (NaN and
  // negative values used to fall back to defaults or bake an empty cloud with exit 0).
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--iso", "nan"}).find("--iso: expected a finite number"), std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--iso", "-1"}).find("--iso: -1 is out of range"), std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--voxel-size", "nan"}).find("--voxel-size: expected a finite number"),
            std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--voxel-size", "-2"}).find("--voxel-size: -2 is out of range"),
            std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--profile-exponent", "nan"}).find("--profile-exponent: expected a finite"),
            std::string::npos);
  EXPECT_NE(error_of({"x.vdb", "-o", "/tmp/x", "--max-size", "4294967312"}).find("--max-size: 4294967312 does not fit"),
            std::string::npos);
  EXPECT_NE(error_of({"--field", "d", "-o", "/tmp/x", "--origin", "nan,0,0"}).find("--origin: expected a finite number"),
            std::string::npos);
  EXPECT_NE(error_of({"--field", "d", "-o", "/tmp/x", "--origin", "1e30,0,0"}).find("--origin: 1e+30 is outside"),
            std::string::npos);
  EXPECT_NE(error_of({"--field", "d", "-o", "/tmp/x", "--sdf-range", "5,1"}).find("--sdf-range: expected MIN,MAX"),
            std::string::npos);
  EXPECT_NE(error_of({"--field", "d", "-o", "/tmp/x", "--sdf-channel", "q"}).find("channel \"q\": expected r, g, b or a"), std::string::npos);
  EXPECT_NE(error_of({"--field", "/nonexistent/slices", "-o", "/tmp/x"}).find("/nonexistent/slices: not a folder"),
            std::string::npos);
}

}  // namespace
}  // namespace cumulo::clouds
