// cumulo::encode_png / write_png: round trip through stb_image for every channel count, the file
// writer, and errors that name the path.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/png.h"

// The decoder is compiled only in this test (it links cumulo_core alone, which has no stb_image).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wshadow"
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#include "tests/support/temp_dir.h"
#pragma GCC diagnostic pop

using namespace cumulo;
namespace fs = std::filesystem;

namespace {

// A 7x5 image whose every byte differs from its neighbours, so a swapped row, channel or stride shows.
std::vector<uint8_t> pattern(uint32_t w, uint32_t h, int ch) {
  std::vector<uint8_t> px(size_t(w) * h * ch);
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 37 + i / 7 * 11) & 0xff);
  return px;
}

std::vector<uint8_t> decode(const std::vector<uint8_t>& png, int& w, int& h, int& ch) {
  stbi_uc* data = stbi_load_from_memory(png.data(), int(png.size()), &w, &h, &ch, 0);
  if (!data) return {};
  std::vector<uint8_t> out(data, data + size_t(w) * h * ch);
  stbi_image_free(data);
  return out;
}

}  // namespace

TEST(Png, RoundTripsEveryChannelCount) {
  const uint32_t W = 7, H = 5;
  for (int ch : {1, 2, 3, 4}) {
    SCOPED_TRACE(ch);
    std::vector<uint8_t> px = pattern(W, H, ch);
    std::vector<uint8_t> png = encode_png(px.data(), W, H, ch);
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(std::string(png.begin() + 1, png.begin() + 4), "PNG");
    int w = 0, h = 0, n = 0;
    EXPECT_EQ(decode(png, w, h, n), px);
    EXPECT_EQ(w, int(W));
    EXPECT_EQ(h, int(H));
    EXPECT_EQ(n, ch);
  }
}

TEST(Png, EncodingIsDeterministic) {
  std::vector<uint8_t> px = pattern(16, 16, 3);
  EXPECT_EQ(encode_png(px.data(), 16, 16, 3), encode_png(px.data(), 16, 16, 3));
}

TEST(Png, WritePngWritesTheEncodedBytes) {
  fs::path dir = cumulo::test::unique_temp_path("cumulo_png_test");
  fs::remove_all(dir);
  fs::path p = dir / "sub" / "a.png";  // missing folders are created
  std::vector<uint8_t> px = pattern(9, 3, 4);
  write_png(p, px.data(), 9, 3, 4);
  EXPECT_EQ(read_file_bytes(p), encode_png(px.data(), 9, 3, 4));
  fs::remove_all(dir);
}

TEST(Png, UnwritablePathNamesIt) {
  std::vector<uint8_t> px = pattern(2, 2, 3);
  try {
    write_png("/proc/cumulo_no_such_dir/x.png", px.data(), 2, 2, 3);
    FAIL() << "expected cumulo::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/cumulo_no_such_dir/x.png"), std::string::npos) << e.what();
  }
}

TEST(Png, BadArgumentsAreRefused) {
  std::vector<uint8_t> px = pattern(2, 2, 4);
  EXPECT_THROW(encode_png(px.data(), 2, 2, 0), Error);
  EXPECT_THROW(encode_png(px.data(), 2, 2, 5), Error);
  EXPECT_THROW(encode_png(px.data(), 0, 2, 3), Error);
  EXPECT_THROW(encode_png(nullptr, 2, 2, 3), Error);
}
