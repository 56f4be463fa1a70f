// Writes the fuzzers' seed corpora with the real writers: DIR/volume/*.nvdf (every encoding, raw
// and zstd, with mips) and DIR/tga/*.tga (raw and RLE, 32-bit; 24-bit and grayscale by hand).
#include <cstdio>
#include <filesystem>
#include <string>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/volume/tga.h"
#include "modules/clouds/volume/volume_file.h"

using namespace cumulo;
using namespace cumulo::clouds;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cumulo_fuzz_seeds DIR\n");
    return 2;
  }
  try {
    const fs::path dir = argv[1];
    fs::remove_all(dir);
    fs::create_directories(dir / "volume");
    fs::create_directories(dir / "tga");
    for (uint32_t e = 1; is_valid_encoding(e); ++e) {
      const auto enc = static_cast<VolumeEncoding>(e);
      Volume v = Volume::create({6, 5, 3}, 8.0f, enc, {{"r", "sdf", -256.0f, 4096.0f}}, is_block_encoding(enc) ? 1 : 2);
      for (auto& level : v.levels)
        for (size_t i = 0; i < level.size(); ++i) level[i] = static_cast<uint8_t>(i * 7 / 5);
      if (enc == VolumeEncoding::R32F)
        for (auto& level : v.levels)
          for (size_t i = 0; i + 3 < level.size(); i += 4) level[i + 3] = 0x3f;  // finite floats
      for (bool compress : {false, true})
        write_file_atomic(dir / "volume" / (std::string(encoding_name(enc)) + (compress ? "_zstd" : "") + ".nvdf"),
                          serialize_volume(v, {.compress = compress}));
    }
    Rgba8Image img{7, 5, std::vector<uint8_t>(7 * 5 * 4)};
    for (size_t i = 0; i < img.rgba.size(); ++i) img.rgba[i] = static_cast<uint8_t>(i < 40 ? 9 : i * 13);
    write_file_atomic(dir / "tga" / "raw32.tga", encode_tga(img, false));
    write_file_atomic(dir / "tga" / "rle32.tga", encode_tga(img, true));
    // 24-bit bottom-left and 8-bit grayscale RLE, the other layouts the decoder reads.
    std::vector<uint8_t> t24 = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, 0};
    for (int i = 0; i < 12; ++i) t24.push_back(static_cast<uint8_t>(i * 20));
    write_file_atomic(dir / "tga" / "raw24.tga", t24);
    std::vector<uint8_t> g8 = {0, 0, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 2, 0, 8, 0x20, 0x84, 77, 0, 5};
    write_file_atomic(dir / "tga" / "rle8.tga", g8);
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
