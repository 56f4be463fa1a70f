#include "modules/clouds/noise/noise_preview.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/error.h"

// stb_image_write's extern implementation lives in cumulo_gpu (screenshots); a private static copy
// here keeps this library free of the GPU layer without duplicate symbols at link time.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace cumulo::clouds {

void write_noise_preview(const std::filesystem::path& path, const NoiseTexture& tex) {
  const int w = tex.width, h = tex.height, ch = tex.channels;
  const int out_w = ch * 2 * w, out_h = 2 * h;
  std::vector<uint8_t> pixels(static_cast<size_t>(out_w) * out_h);
  for (int c = 0; c < ch; ++c)
    for (int y = 0; y < out_h; ++y)
      for (int x = 0; x < 2 * w; ++x) {
        float v = tex.at(0, x % w, y % h, 0, c);
        pixels[static_cast<size_t>(y) * out_w + c * 2 * w + x] =
            static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
      }
  if (!stbi_write_png(path.string().c_str(), out_w, out_h, 1, pixels.data(), out_w))
    fail("%s: cannot write the PNG preview", path.string().c_str());
}

}  // namespace cumulo::clouds
