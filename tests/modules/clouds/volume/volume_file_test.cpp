// .nvdf roundtrips for every encoding (raw and zstd) and every corruption the loader must refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "modules/clouds/volume/volume_file.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

const VolumeEncoding kAll[] = {VolumeEncoding::R8,     VolumeEncoding::RG8,  VolumeEncoding::RGBA8,
                               VolumeEncoding::R16,    VolumeEncoding::RGBA16, VolumeEncoding::R32F,
                               VolumeEncoding::R4G4B4A4, VolumeEncoding::BC1, VolumeEncoding::BC4,
                               VolumeEncoding::BC7};

// A volume with smooth (compressible) data plus a little noise, odd sizes to exercise mips and
// partial BC1 blocks.
Volume make_volume(VolumeEncoding e, uint32_t mips) {
  std::vector<VolumeChannel> ch;
  const uint32_t n = std::min(3u, encoding_components(e));
  const char* sem[] = {"dimensional_profile", "detail_type", "density_scale"};
  for (uint32_t i = 0; i < n; ++i) ch.push_back({std::string("c") + char('0' + i), sem[i], 0.0f, 1.0f});
  if (e == VolumeEncoding::R16) ch[0] = {"r", "sdf", kSdfRangeMin, kSdfRangeMax};
  Volume v = Volume::create({13, 9, 6}, 8.0f, e, ch, mips);
  v.bounds_min = {-52.0f, -36.0f, 100.0f};
  v.bounds_max = {52.0f, 36.0f, 148.0f};
  std::mt19937 rng(7);
  for (auto& level : v.levels)
    for (size_t i = 0; i < level.size(); ++i) level[i] = static_cast<uint8_t>((i / 7) + (rng() % 3));
  if (e == VolumeEncoding::R32F)  // valid floats, not arbitrary bit patterns
    for (uint32_t l = 0; l < v.mip_count(); ++l) {
      glm::uvec3 s = v.level_size(l);
      for (uint32_t z = 0; z < s.z; ++z)
        for (uint32_t y = 0; y < s.y; ++y)
          for (uint32_t x = 0; x < s.x; ++x) v.set_texel(x, y, z, 0, float(x) * 0.5f - float(y * z), l);
    }
  return v;
}

void expect_same(const Volume& a, const Volume& b) {
  EXPECT_EQ(a.size, b.size);
  EXPECT_EQ(a.voxel_size, b.voxel_size);
  EXPECT_EQ(a.bounds_min, b.bounds_min);
  EXPECT_EQ(a.bounds_max, b.bounds_max);
  EXPECT_EQ(a.encoding, b.encoding);
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (size_t i = 0; i < a.channels.size(); ++i) {
    EXPECT_EQ(a.channels[i].name, b.channels[i].name);
    EXPECT_EQ(a.channels[i].semantic, b.channels[i].semantic);
    EXPECT_EQ(a.channels[i].decode_min, b.channels[i].decode_min);
    EXPECT_EQ(a.channels[i].decode_max, b.channels[i].decode_max);
  }
  EXPECT_EQ(a.levels, b.levels);
}

std::string error_of(const std::vector<uint8_t>& bytes, const VolumeLoadLimits& limits = {}) {
  try {
    parse_volume(bytes, "clouds.nvdf", limits);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_ERROR(bytes, fragment)                                        \
  do {                                                                       \
    std::string msg = error_of(bytes);                                       \
    EXPECT_NE(msg.find("clouds.nvdf: "), std::string::npos) << msg;         \
    EXPECT_NE(msg.find(fragment), std::string::npos) << "got: " << msg;     \
  } while (0)

TEST(VolumeFile, RoundtripEveryEncodingRawAndZstd) {
  for (VolumeEncoding e : kAll)
    for (bool compress : {false, true}) {
      SCOPED_TRACE(std::string(encoding_name(e)) + (compress ? " zstd" : " raw"));
      Volume v = make_volume(e, 3);
      std::vector<uint8_t> bytes = serialize_volume(v, {.compress = compress});
      Volume back = parse_volume(bytes, "mem");
      expect_same(v, back);
    }
}

TEST(VolumeFile, CompressionShrinksSmoothData) {
  Volume v = Volume::create({64, 64, 64}, 8.0f, VolumeEncoding::RGBA8, {{"r", "dimensional_profile"}});
  for (auto& b : v.levels[0]) b = 42;
  EXPECT_LT(serialize_volume(v, {.compress = true}).size(), serialize_volume(v, {.compress = false}).size() / 10);
}

TEST(VolumeFile, SaveAndLoadFile) {
  fs::path dir = cumulo::test::unique_temp_path("cumulo_volume_file_test");
  fs::create_directories(dir);
  Volume v = make_volume(VolumeEncoding::R16, 2);
  save_volume(dir / "field.nvdf", v);
  expect_same(v, load_volume(dir / "field.nvdf"));
  fs::remove_all(dir);
}

TEST(VolumeFile, MissingFileNamesIt) {
  try {
    load_volume("/nonexistent/dir/missing.nvdf");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.nvdf"), std::string::npos) << e.what();
  }
}

TEST(VolumeFile, TruncatedAtManyOffsets) {
  for (bool compress : {false, true}) {
    std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA8, 2), {.compress = compress});
    for (size_t cut : {size_t(0), size_t(4), size_t(11), size_t(50), size_t(100), size_t(180), bytes.size() / 2,
                       bytes.size() - 1}) {
      SCOPED_TRACE(cut);
      std::vector<uint8_t> t(bytes.begin(), bytes.begin() + static_cast<ptrdiff_t>(cut));
      std::string msg = error_of(t);
      EXPECT_NE(msg.find("clouds.nvdf: "), std::string::npos) << msg;
      // Cut inside the magic reads as "not a volume", anywhere else as truncated.
      if (cut >= 8) {
        EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
      }
    }
  }
}

TEST(VolumeFile, TruncatedPayloadMessageGivesSizes) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::R8, 1), {.compress = false});
  bytes.resize(bytes.size() - 100);
  EXPECT_ERROR(bytes, "truncated: header says 702 payload bytes, file has 602");
}

TEST(VolumeFile, NonFiniteR32FTexelsAreRefused) {
  // An all-NaN SDF used to bake an empty cloud with exit 0: stored floats follow the outside-number rule.
  for (float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    Volume v = make_volume(VolumeEncoding::R32F, 1);
    v.set_texel(3, 2, 1, 0, bad);
    const std::vector<uint8_t> bytes = serialize_volume(v);
    try {
      parse_volume(bytes, "nan.nvdf");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("nan.nvdf: mip level 0: texel"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not a finite number"), std::string::npos) << e.what();
    }
  }
}

TEST(VolumeFile, TrailingGarbage) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::R8, 1));
  bytes.push_back(0);
  EXPECT_ERROR(bytes, "1 bytes of trailing garbage");
}

TEST(VolumeFile, FlippedPayloadByteIsChecksumError) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA16, 2), {.compress = false});
  bytes[bytes.size() - 10] ^= 0x10;
  EXPECT_ERROR(bytes, "payload checksum mismatch");
}

TEST(VolumeFile, FlippedCompressedByteIsRefused) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA8, 3), {.compress = true});
  for (size_t back : {size_t(5), size_t(40), size_t(100)}) {
    std::vector<uint8_t> b = bytes;
    b[b.size() - back] ^= 0x01;
    std::string msg = error_of(b);
    EXPECT_NE(msg.find("clouds.nvdf: "), std::string::npos) << msg;
  }
}

TEST(VolumeFile, FlippedHeaderByteIsRefused) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA8, 2));
  // Bounds (offset 48..71) are free floats: only the header checksum catches a flip there.
  std::vector<uint8_t> b = bytes;
  b[50] ^= 0x01;
  EXPECT_ERROR(b, "header checksum mismatch");
}

TEST(VolumeFile, BadMagic) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::R8, 1));
  bytes[1] = 'X';
  EXPECT_ERROR(bytes, "bad magic");
}

TEST(VolumeFile, BadVersion) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::R8, 1));
  bytes[8] = 99;
  EXPECT_ERROR(bytes, "unsupported volume file version 99");
}

// Rewrites a u32 header field and fixes the header checksum, so the semantic check (not the
// checksum) must catch it.
std::vector<uint8_t> with_field(std::vector<uint8_t> bytes, size_t offset, uint32_t value) {
  uint32_t header_bytes;
  std::memcpy(&header_bytes, &bytes[12], 4);
  std::memcpy(&bytes[offset], &value, 4);
  uint64_t h = hash64(bytes.data(), header_bytes - 8);
  std::memcpy(&bytes[header_bytes - 8], &h, 8);
  return bytes;
}

TEST(VolumeFile, WrongSizesAreRefused) {
  const std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA8, 2), {.compress = false});
  EXPECT_ERROR(with_field(bytes, 24, 14), "mip level 0: header says 2808 bytes, rgba8 at 14x9x6 needs 3024");
  EXPECT_ERROR(with_field(bytes, 24, 0), "axis x must be 1..4096");
  EXPECT_ERROR(with_field(bytes, 28, 5000), "axis y must be 1..4096");
  EXPECT_ERROR(with_field(bytes, 20, 77), "unknown encoding 77");
  EXPECT_ERROR(with_field(bytes, 20, uint32_t(VolumeEncoding::R8)), "mip level 0: header says");
  EXPECT_ERROR(with_field(bytes, 36, 9), "mip count 9");
  EXPECT_ERROR(with_field(bytes, 40, 7), "channel count 7");
  EXPECT_ERROR(with_field(bytes, 16, 0x80), "unknown flags");
  EXPECT_ERROR(with_field(bytes, 12, 20), "header size field");
  // Bit patterns of floats: NaN voxel size, inverted bounds.
  EXPECT_ERROR(with_field(bytes, 44, 0x7fc00000u), "voxel size");
  float big = 1e9f;
  uint32_t bits;
  std::memcpy(&bits, &big, 4);
  EXPECT_ERROR(with_field(bytes, 48, bits), "bounds axis x");
}

TEST(VolumeFile, PayloadSizeFieldMismatch) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::R8, 1), {.compress = false});
  EXPECT_ERROR(with_field(bytes, 72, 703), "header says 703 payload bytes, its levels need 702");
}

TEST(VolumeFile, LimitOnPayload) {
  std::vector<uint8_t> bytes = serialize_volume(make_volume(VolumeEncoding::RGBA8, 1));
  std::string msg = error_of(bytes, {.max_dimension = 4096, .max_payload_bytes = 100});
  EXPECT_NE(msg.find("over the limit"), std::string::npos) << msg;
  msg = error_of(bytes, {.max_dimension = 8, .max_payload_bytes = 1u << 30});
  EXPECT_NE(msg.find("must be 1..8"), std::string::npos) << msg;
}

TEST(VolumeFile, WriterRefusesInconsistentVolume) {
  Volume v = make_volume(VolumeEncoding::R8, 1);
  v.levels[0].pop_back();
  EXPECT_THROW(serialize_volume(v), Error);
  v = make_volume(VolumeEncoding::R8, 1);
  v.channels.push_back({"x", "y"});
  EXPECT_THROW(serialize_volume(v), Error);
}

}  // namespace
}  // namespace cumulo::clouds
