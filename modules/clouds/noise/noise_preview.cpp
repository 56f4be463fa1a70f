#include "modules/clouds/noise/noise_preview.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/core/png.h"

namespace cumulo::clouds {

std::vector<uint8_t> encode_noise_preview(const NoiseTexture& tex) {
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
  return cumulo::encode_png(pixels.data(), uint32_t(out_w), uint32_t(out_h), 1);
}

}  // namespace cumulo::clouds
