// TGA codec and the TGA-slice importer, on slices the test writes itself.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/tga.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

Rgba8Image gradient(uint32_t w, uint32_t h, uint8_t salt) {
  Rgba8Image img{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      uint8_t* p = &img.rgba[(size_t(y) * w + x) * 4];
      p[0] = uint8_t(x * 16 + salt), p[1] = uint8_t(y * 8), p[2] = uint8_t(x < w / 2 ? 7 : 7 + salt), p[3] = 200;
    }
  return img;
}

TEST(Tga, RoundtripRawAndRle) {
  Rgba8Image img = gradient(13, 7, 3);
  for (bool rle : {false, true}) {
    Rgba8Image back = decode_tga(encode_tga(img, rle), "t.tga");
    EXPECT_EQ(back.width, 13u);
    EXPECT_EQ(back.height, 7u);
    EXPECT_EQ(back.rgba, img.rgba);
  }
  EXPECT_LT(encode_tga(Rgba8Image{64, 64, std::vector<uint8_t>(64 * 64 * 4, 9)}, true).size(), 64u * 64u);
}

// Handwritten 2x2 24-bit bottom-left-origin file, the most common layout from image tools.
TEST(Tga, BottomLeftOrigin24Bit) {
  std::vector<uint8_t> f(18, 0);
  f[2] = 2, f[12] = 2, f[14] = 2, f[16] = 24, f[17] = 0;
  // File rows: bottom row first. BGR.
  const uint8_t px[] = {0, 0, 255, /**/ 0, 255, 0, /**/ 255, 0, 0, /**/ 10, 20, 30};
  f.insert(f.end(), px, px + sizeof px);
  Rgba8Image img = decode_tga(f, "b.tga");
  const uint8_t* top_left = img.pixel(0, 0);  // file row 1, first pixel: B=255 -> blue
  EXPECT_EQ(top_left[2], 255);
  EXPECT_EQ(top_left[3], 255);
  const uint8_t* bottom_left = img.pixel(0, 1);  // red
  EXPECT_EQ(bottom_left[0], 255);
  EXPECT_EQ(img.pixel(1, 0)[0], 30);
}

TEST(Tga, RleRunsMayCrossRowsAndGrayscale) {
  std::vector<uint8_t> f(18, 0);
  f[2] = 11, f[12] = 3, f[14] = 2, f[16] = 8, f[17] = 0x20;
  f.push_back(0x80 | 4), f.push_back(77);  // 5 pixels of 77 cross the row boundary
  f.push_back(0), f.push_back(5);          // one raw pixel
  Rgba8Image img = decode_tga(f, "g.tga");
  EXPECT_EQ(img.pixel(1, 1)[1], 77);
  EXPECT_EQ(img.pixel(2, 1)[0], 5);
}

TEST(Tga, ErrorsNameTheFile) {
  std::vector<uint8_t> good = encode_tga(gradient(4, 4, 0), true);
  EXPECT_NE(error_of([&] { decode_tga(std::span(good).first(10), "x.tga"); }).find("x.tga: truncated TGA"), std::string::npos);
  EXPECT_NE(error_of([&] { decode_tga(std::span(good).first(good.size() - 2), "x.tga"); }).find("x.tga: truncated TGA"),
            std::string::npos);
  std::vector<uint8_t> bad = good;
  bad[2] = 1;  // colour-mapped
  EXPECT_NE(error_of([&] { decode_tga(bad, "x.tga"); }).find("unsupported TGA image type 1"), std::string::npos);
  bad = good;
  bad[16] = 16;
  EXPECT_NE(error_of([&] { decode_tga(bad, "x.tga"); }).find("pixel depth 16"), std::string::npos);
  bad = good;
  bad[18] = 0xff;  // run of 128 overruns a 16-pixel image
  EXPECT_NE(error_of([&] { decode_tga(bad, "x.tga"); }).find("overrun"), std::string::npos);
}

TEST(NumberedSlices, NaturalOrderAndErrors) {
  cumulo::test::TempDir dir("cumulo_volume_slices_order");
  for (const char* n : {"cloud_slice_10.tga", "cloud_slice_2.TGA", "cloud_slice_1.tga", "readme.txt"})
    write_file_atomic(dir.path / n, encode_tga(gradient(2, 2, 0)));
  std::vector<fs::path> files = numbered_slices(dir.path);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0].filename(), "cloud_slice_1.tga");
  EXPECT_EQ(files[1].filename(), "cloud_slice_2.TGA");
  EXPECT_EQ(files[2].filename(), "cloud_slice_10.tga");

  write_file_atomic(dir.path / "cloud_slice_002.tga", encode_tga(gradient(2, 2, 0)));
  std::string msg = error_of([&] { numbered_slices(dir.path); });
  EXPECT_NE(msg.find("slice number 2 also used by"), std::string::npos) << msg;
  fs::remove(dir.path / "cloud_slice_002.tga");

  write_file_atomic(dir.path / "cover.tga", encode_tga(gradient(2, 2, 0)));
  msg = error_of([&] { numbered_slices(dir.path); });
  EXPECT_NE(msg.find("cover.tga: slice file name has no number"), std::string::npos) << msg;

  cumulo::test::TempDir empty("cumulo_volume_slices_empty");
  msg = error_of([&] { numbered_slices(empty.path); });
  EXPECT_NE(msg.find("no .tga slices"), std::string::npos) << msg;
  msg = error_of([&] { numbered_slices(empty.path / "missing"); });
  EXPECT_NE(msg.find("missing: not a folder"), std::string::npos) << msg;
}

// A 16x12x6 cloudscape as slices: modeling (profile in R, detail in G, density in B) and field
// (SDF in R, -256..4096 -> 0..255).
struct SliceSet {
  cumulo::test::TempDir modeling{"cumulo_volume_slices_modeling"}, field{"cumulo_volume_slices_field"};
  static uint8_t profile(uint32_t x, uint32_t y, uint32_t z) { return (x >= 4 && x < 12 && y >= 3 && y < 9 && z >= 1 && z < 5) ? uint8_t(40 * z + x) : 0; }
  static uint8_t sdf(uint32_t x, uint32_t y, uint32_t z) { return uint8_t(x * 10 + y + z); }
  SliceSet() {
    for (uint32_t z = 0; z < 6; ++z) {
      Rgba8Image m{16, 12, std::vector<uint8_t>(16 * 12 * 4)}, f = m;
      for (uint32_t y = 0; y < 12; ++y)
        for (uint32_t x = 0; x < 16; ++x) {
          uint8_t* p = &m.rgba[(y * 16 + x) * 4];
          p[0] = profile(x, y, z), p[1] = uint8_t(y * 20), p[2] = uint8_t(255 - x), p[3] = 255;
          uint8_t* q = &f.rgba[(y * 16 + x) * 4];
          q[0] = sdf(x, y, z), q[1] = 0, q[2] = 0, q[3] = 255;
        }
      // Numbers without zero padding, so lexical order would be wrong; alternate raw and RLE.
      write_file_atomic(modeling.path / ("modeling_" + std::to_string(z) + ".tga"), encode_tga(m, z % 2));
      write_file_atomic(field.path / ("field_" + std::to_string(z * 5) + ".tga"), encode_tga(f, z % 2 == 0));
    }
  }
};

TEST(ImportSlices, ModelingAndFieldDefaults) {
  SliceSet s;
  SliceImportOptions o;  // slices are horizontal layers: volume texel (x, y, z) = pixel (x, row z) of slice y
  o.origin = glm::vec3(100, 200, 300);
  CloudscapeVolumes v = import_tga_slices(s.modeling.path, s.field.path, o);
  const Volume& m = v.modeling;
  const Volume& f = v.field;
  EXPECT_EQ(m.size, glm::uvec3(16, 6, 12));
  EXPECT_EQ(m.bounds_min, glm::vec3(100, 200, 300));
  EXPECT_EQ(m.bounds_max, glm::vec3(100 + 128, 200 + 48, 300 + 96));
  check_modeling_volume(m, "m");
  check_field_volume(f, "f");
  const uint32_t cp = m.channel(kDimensionalProfile, ""), cd = m.channel(kDetailType, ""),
                 cs = m.channel(kDensityScale, ""), cf = f.channel(kSignedDistance, "");
  for (uint32_t z : {0u, 4u, 11u})
    for (uint32_t y : {0u, 2u, 5u})
      for (uint32_t x : {0u, 5u, 15u}) {
        EXPECT_FLOAT_EQ(m.texel(x, y, z, cp), SliceSet::profile(x, z, y) / 255.0f);
        EXPECT_FLOAT_EQ(m.texel(x, y, z, cd), float(z * 20) / 255.0f);
        EXPECT_FLOAT_EQ(m.texel(x, y, z, cs), float(255 - x) / 255.0f);
        // The 16-bit field rounds down: never above the source value, less than a step below.
        const float want = -256.0f + 4352.0f * SliceSet::sdf(x, z, y) / 255.0f;
        EXPECT_LE(f.decoded(x, y, z, cf), want + 1e-3f);
        EXPECT_GE(f.decoded(x, y, z, cf), want - 4352.0f / 65535.0f - 1e-3f);
      }
}

TEST(ImportSlices, DefaultOriginAndVerticalSliceAxis) {
  SliceSet s;
  SliceImportOptions o;
  CloudscapeVolumes v = import_tga_slices(s.modeling.path, std::nullopt, o);
  // Centred on x and z with its base at y = 0, like the baker's default box.
  EXPECT_EQ(v.modeling.bounds_min, glm::vec3(-64, 0, -48));
  EXPECT_EQ(v.modeling.bounds_max, glm::vec3(64, 48, 48));
  // Slices as vertical layers of constant z, the image's top row at the highest y.
  o.axis = SliceAxis::Z;
  v = import_tga_slices(s.modeling.path, std::nullopt, o);
  EXPECT_EQ(v.modeling.size, glm::uvec3(16, 12, 6));
  for (uint32_t z : {0u, 3u})
    for (uint32_t y : {0u, 5u, 11u})
      for (uint32_t x : {4u, 9u})
        EXPECT_FLOAT_EQ(v.modeling.texel(x, y, z, 0), SliceSet::profile(x, 11 - y, z) / 255.0f);
}

TEST(ImportSlices, ChannelMappingAndRangeOptions) {
  SliceSet s;
  SliceImportOptions o;
  o.profile_channel = 2, o.detail_channel = 0, o.density_channel = 1;
  o.sdf_min = 0.0f, o.sdf_max = 255.0f;  // 1 m per step
  CloudscapeVolumes v = import_tga_slices(s.modeling.path, s.field.path, o);
  EXPECT_FLOAT_EQ(v.modeling.texel(3, 0, 0, 0), float(255 - 3) / 255.0f);
  EXPECT_FLOAT_EQ(v.modeling.texel(3, 5, 2, 2), 40.0f / 255.0f);  // G = row * 20, row = z
  // Stored in the standard -256..4096 field range whatever the source range was.
  EXPECT_EQ(v.field.channels[0].decode_min, kSdfRangeMin);
  EXPECT_NEAR(v.field.decoded(7, 1, 3, 0), float(SliceSet::sdf(7, 3, 1)), 0.07f);
  EXPECT_EQ(parse_channel_letter("A"), 3u);
  EXPECT_THROW(parse_channel_letter("x"), Error);
}

TEST(ImportSlices, MissingFieldIsDerivedFromProfile) {
  SliceSet s;
  SliceImportOptions o;
  o.voxel_size = 4.0f;
  CloudscapeVolumes v = import_tga_slices(s.modeling.path, std::nullopt, o);
  // Inside: columns 4..11, rows (z) 3..8, slices (y) 1..4. Voxel (8, 2, 6) is 2 voxels above the
  // outside layer y = 0; voxel (0, 2, 6) is 4 voxels left of x = 4. Surface halfway: -+half voxel.
  EXPECT_NEAR(v.field.decoded(8, 2, 6, 0), -(2 * 4.0f - 2.0f), 0.07f);
  EXPECT_NEAR(v.field.decoded(0, 2, 6, 0), 4 * 4.0f - 2.0f, 0.07f);
  // Missing modeling: derived from the field's SDF with defaults.
  CloudscapeVolumes w = import_tga_slices(std::nullopt, s.field.path, o);
  EXPECT_FLOAT_EQ(w.modeling.texel(0, 0, 0, w.modeling.channel(kDimensionalProfile, "")), 1.0f);  // sdf -256
  EXPECT_FLOAT_EQ(w.modeling.texel(15, 0, 0, 0), 0.0f);
  EXPECT_NEAR(w.modeling.texel(0, 0, 0, w.modeling.channel(kDetailType, "")), 0.5f, 1.0f / 255.0f);
}

TEST(ImportSlices, ErrorsNameFiles) {
  SliceSet s;
  // A slice of a different size.
  write_file_atomic(s.modeling.path / "modeling_6.tga", encode_tga(gradient(8, 12, 0)));
  std::string msg = error_of([&] { import_tga_slices(s.modeling.path, std::nullopt, {}); });
  EXPECT_NE(msg.find("modeling_6.tga: slice is 8x12, but modeling_0.tga is 16x12"), std::string::npos) << msg;
  // Unreadable (corrupt) slice.
  write_file_atomic(s.modeling.path / "modeling_6.tga", std::string("not a tga"));
  msg = error_of([&] { import_tga_slices(s.modeling.path, std::nullopt, {}); });
  EXPECT_NE(msg.find("modeling_6.tga: truncated TGA"), std::string::npos) << msg;
  fs::remove(s.modeling.path / "modeling_6.tga");
  // Field with a different slice count.
  fs::remove(s.field.path / "field_25.tga");
  msg = error_of([&] { import_tga_slices(s.modeling.path, s.field.path, {}); });
  EXPECT_NE(msg.find("field slices are 16x12x5, modeling slices"), std::string::npos) << msg;
}

TEST(ImportSlices, SavedPairLoadsBack) {
  SliceSet s;
  cumulo::test::TempDir out("cumulo_volume_slices_out");
  CloudscapeVolumes v = import_tga_slices(s.modeling.path, s.field.path, {});
  save_cloudscape(out.path, v);
  Volume m = load_volume(out.path / kModelingFileName);
  Volume f = load_volume(out.path / kFieldFileName);
  EXPECT_EQ(m.levels, v.modeling.levels);
  EXPECT_EQ(f.levels, v.field.levels);
}

}  // namespace
}  // namespace cumulo::clouds
