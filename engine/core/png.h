#pragma once
// The engine's one PNG encoder (stb_image_write, compiled only in png.cpp: no other file may define
// STB_IMAGE_WRITE_IMPLEMENTATION). Used by screenshots, glTF textures, noise previews and bake slices.
//
//   std::vector<uint8_t> bytes = cumulo::encode_png(rgb.data(), w, h, 3);
//   cumulo::write_png("out/slice.png", gray.data(), w, h, 1);   // atomic; throws cumulo::Error naming the path
#include <cstdint>
#include <filesystem>
#include <vector>

namespace cumulo {

// pixels: width * height * channels bytes (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA), tightly packed, top
// row first. stb's default compression (zlib level 8, adaptive filters), so output is deterministic.
std::vector<uint8_t> encode_png(const uint8_t* pixels, uint32_t width, uint32_t height, int channels);
void write_png(const std::filesystem::path& path, const uint8_t* pixels, uint32_t width, uint32_t height,
               int channels);

// Reads a PNG (any bit depth / colour type stb_image decodes) as RGBA8, top row first. Throws
// cumulo::Error naming the path for a missing, unreadable or malformed file.
struct ImageRgba8 {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};
ImageRgba8 read_png_rgba8(const std::filesystem::path& path);

}  // namespace cumulo
