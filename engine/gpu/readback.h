#pragma once
// Offscreen readback: image -> host memory -> RGBA8 -> PNG (headless screenshots, render tests).
// PNG encoding is cumulo::write_png (engine/core/png.h); gpu::write_png adds the Rgba8Image checks.
//
//   gpu::Rgba8Image shot = gpu::read_image_rgba8(ctx, color_target);   // waits for the GPU
//   gpu::write_png("out/sample.png", shot);                             // throws cumulo::Error naming the path
//   std::vector<uint8_t> raw = gpu::read_image_bytes(ctx, volume, /*mip=*/1);  // tightly packed texels
//
// The image must be in image.layout() (helpers and the render graph keep it current) and have
// TRANSFER_SRC usage (gpu::Image adds it for color formats). It is returned to that layout afterwards
// (UNDEFINED becomes TRANSFER_SRC_OPTIMAL).
#include <cstdint>
#include <filesystem>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;
class Image;

struct Rgba8Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width * height * 4, row-major, top row first
  const uint8_t* at(uint32_t x, uint32_t y) const { return &pixels[(size_t(y) * width + x) * 4]; }
};

std::vector<uint8_t> read_image_bytes(Context& ctx, Image& image, uint32_t mip = 0, uint32_t layer = 0);
// Converts 2D color formats (8-bit UNORM/SRGB incl. BGRA, 16/32-bit float, R8, RG, 10-bit packed).
// Float formats are clamped to [0,1]; `srgb_encode` applies the sRGB curve to linear float data.
Rgba8Image read_image_rgba8(Context& ctx, Image& image, bool srgb_encode = false);
// Pure conversion (unit-testable): `count` texels of `format` -> RGBA8. Throws for unknown formats.
std::vector<uint8_t> convert_to_rgba8(VkFormat format, const void* texels, size_t count, bool srgb_encode = false);
void write_png(const std::filesystem::path& path, const Rgba8Image& image);

float half_to_float(uint16_t h);

}  // namespace cumulo::gpu
