#pragma once
// Minimal PNG writer (8-bit RGB, zlib "stored" deflate blocks: no compression library needed) for
// the bake's cross-section images.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace cumulo::clouds::bake {

// rgb: width * height * 3 bytes, row 0 at the top. Returns the file bytes.
std::vector<uint8_t> encode_png_rgb(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb);
void write_png_rgb(const std::filesystem::path& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgb);

}  // namespace cumulo::clouds::bake
