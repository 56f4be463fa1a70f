#pragma once
// Reads a PNG a test wrote (a `cumulo run --screenshot`) into RGBA8. Carries its own static copy of the
// stb decoder (static, like load_png, so every source file that includes it has its own): the scene
// library's copy is private to it.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

#include "engine/core/file_io.h"

namespace cumulo::test {

struct Png {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
  const uint8_t* px(int x, int y) const { return &rgba[(size_t(y) * w + x) * 4]; }
  int at(int x, int y, int c) const { return px(x, y)[c]; }
};

// Empty (w = 0) when the file is not a PNG.
static Png load_png(const std::filesystem::path& path) {
  std::string bytes = read_file_text(path);
  Png img;
  int n = 0;
  uint8_t* d = stbi_load_from_memory(reinterpret_cast<const uint8_t*>(bytes.data()), int(bytes.size()), &img.w, &img.h,
                                     &n, 4);
  if (d) {
    img.rgba.assign(d, d + size_t(img.w) * img.h * 4);
    stbi_image_free(d);
  }
  return img;
}

}  // namespace cumulo::test
