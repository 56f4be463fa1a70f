#pragma once
// A small, strict TGA codec for volume slices (the form in which NVDFs are commonly shared, 2023
// talk: "NVDF's ... in the form of TGA Slices"). Our own rather than stb_image so it can be fuzzed
// on its own and does not clash with the engine's stb_image instance.
//
// Reads: image types 2 (truecolor) and 10 (RLE truecolor) at 24 or 32 bits, 3 / 11 (grayscale,
// raw / RLE) at 8 bits; either origin (bottom-left or top-left) and right-to-left rows; an image ID
// and a (skipped) colour map. Writes: 32-bit truecolor, raw or RLE, top-left origin.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace cumulo::clouds {

struct Rgba8Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // row 0 is the top row; 4 bytes per pixel
  const uint8_t* pixel(uint32_t x, uint32_t y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

struct TgaLimits {
  uint32_t max_dimension = 8192;
};

// Throws cumulo::Error("<name>: <what>") for truncated data, unsupported types, bad RLE packets.
Rgba8Image decode_tga(std::span<const uint8_t> bytes, const std::string& name, const TgaLimits& limits = {});
Rgba8Image load_tga(const std::filesystem::path& path, const TgaLimits& limits = {});
// Width and height from the 18-byte header, so a caller can budget the memory a set of slices will take before
// decoding any of them. The header is checked as decode_tga checks it (type, depth, size, the pixel bytes the file
// must hold): a file that is no TGA throws cumulo::Error naming it here, before its made-up size reaches a budget.
std::pair<uint32_t, uint32_t> peek_tga_size(const std::filesystem::path& path, const TgaLimits& limits = {});
std::vector<uint8_t> encode_tga(const Rgba8Image& image, bool rle = false);

}  // namespace cumulo::clouds
