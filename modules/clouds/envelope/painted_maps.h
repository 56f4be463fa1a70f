#pragma once
// Painted envelope maps (OrographicClouds "maps"): grey PNGs of 8 or 16 bits read at full precision. The engine's
// read_png_rgba8 reduces 16-bit images to 8 bits (3 m steps over an 800 m range), so this reader keeps its own
// static, PNG-only stb_image, as the glTF loader and the tests do.
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds::envelope {

struct GreyImage {
  uint32_t width = 0, height = 0;  // 0: absent
  std::vector<float> values;       // 0..1, row 0 first
  bool empty() const { return values.empty(); }
  // Bilinear at uv in [0, 1]^2 over the whole image (texel centres at (i + 0.5) / width), clamped to the edge.
  float sample(glm::vec2 uv) const;
};

struct PaintedMaps {
  GreyImage bottom, top, coverage, detail;  // coverage and detail may be empty
};

// Throws cumulo::Error naming the path for a missing, unreadable or malformed file. Colour is reduced to luminance;
// alpha is ignored.
GreyImage read_grey_png(const std::filesystem::path& path);

}  // namespace cumulo::clouds::envelope
