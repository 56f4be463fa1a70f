#include "modules/clouds/envelope/painted_maps.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

// Static: the glTF loader and png.cpp keep copies of their own, and this one must not clash with them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG
#define STBI_MAX_DIMENSIONS 16384
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace cumulo::clouds::envelope {

float GreyImage::sample(glm::vec2 uv) const {
  if (empty()) return 0.0f;
  const float x = std::clamp(uv.x * float(width) - 0.5f, 0.0f, float(width - 1));
  const float y = std::clamp(uv.y * float(height) - 0.5f, 0.0f, float(height - 1));
  const uint32_t x0 = std::min(uint32_t(x), width - 1), y0 = std::min(uint32_t(y), height - 1);
  const uint32_t x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = x - float(x0), fy = y - float(y0);
  auto at = [&](uint32_t i, uint32_t j) { return values[size_t(j) * width + i]; };
  const float a = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
  const float b = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
  return a + (b - a) * fy;
}

GreyImage read_grey_png(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  if (bytes.size() > size_t(INT_MAX)) fail("%s: too large for the PNG decoder", path.string().c_str());
  const int n = int(bytes.size());
  int w = 0, h = 0, comp = 0;
  GreyImage img;
  if (stbi_is_16_bit_from_memory(bytes.data(), n)) {
    stbi_us* px = stbi_load_16_from_memory(bytes.data(), n, &w, &h, &comp, 1);
    if (!px) fail("%s: not a readable PNG (%s)", path.string().c_str(), stbi_failure_reason());
    img.values.resize(size_t(w) * size_t(h));
    for (size_t i = 0; i < img.values.size(); ++i) img.values[i] = float(px[i]) / 65535.0f;
    stbi_image_free(px);
  } else {
    stbi_uc* px = stbi_load_from_memory(bytes.data(), n, &w, &h, &comp, 1);
    if (!px) fail("%s: not a readable PNG (%s)", path.string().c_str(), stbi_failure_reason());
    img.values.resize(size_t(w) * size_t(h));
    for (size_t i = 0; i < img.values.size(); ++i) img.values[i] = float(px[i]) / 255.0f;
    stbi_image_free(px);
  }
  img.width = uint32_t(w);
  img.height = uint32_t(h);
  return img;
}

}  // namespace cumulo::clouds::envelope
