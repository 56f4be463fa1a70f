#include "engine/core/png.h"

#include <climits>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

// The only stb_image_write implementation in the program (extern linkage: cumulo_core is linked by
// every library, so nobody needs a private copy).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>
// A private stb_image for PNG reading (static: the glTF loader has its own for textures).
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG
#define STBI_MAX_DIMENSIONS 16384
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace cumulo {

namespace {

void check_args(const uint8_t* pixels, uint32_t width, uint32_t height, int channels, const char* what) {
  if (channels < 1 || channels > 4) fail("%s: PNG needs 1 to 4 channels, got %d", what, channels);
  if (width == 0 || height == 0) fail("%s: cannot encode an empty %ux%u image as PNG", what, width, height);
  // stb works in int: the row stride and the whole image must fit.
  if (uint64_t(width) * uint32_t(channels) > uint64_t(INT_MAX) / 2 || height > uint32_t(INT_MAX) ||
      uint64_t(width) * height * uint32_t(channels) > uint64_t(INT_MAX) / 2)
    fail("%s: %ux%u image is too large for the PNG encoder", what, width, height);
  if (!pixels) fail("%s: no pixel data", what);
}

std::vector<uint8_t> encode(const uint8_t* pixels, uint32_t width, uint32_t height, int channels,
                            const char* what) {
  check_args(pixels, width, height, channels, what);
  std::vector<uint8_t> png;
  auto sink = [](void* ctx, void* data, int size) {
    auto* v = static_cast<std::vector<uint8_t>*>(ctx);
    v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  };
  if (!stbi_write_png_to_func(sink, &png, int(width), int(height), channels, pixels, int(width) * channels))
    fail("%s: PNG encoding of a %ux%u image with %d channels failed", what, width, height, channels);
  return png;
}

}  // namespace

std::vector<uint8_t> encode_png(const uint8_t* pixels, uint32_t width, uint32_t height, int channels) {
  return encode(pixels, width, height, channels, "encode_png");
}

void write_png(const std::filesystem::path& path, const uint8_t* pixels, uint32_t width, uint32_t height,
               int channels) {
  // write_file_atomic's own errors already name the path.
  write_file_atomic(path, encode(pixels, width, height, channels, path.c_str()));
}

ImageRgba8 read_png_rgba8(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  if (bytes.size() > size_t(INT_MAX)) fail("%s: too large for the PNG decoder", path.string().c_str());
  int w = 0, h = 0, comp = 0;
  stbi_uc* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &w, &h, &comp, 4);
  if (!px) fail("%s: not a readable PNG (%s)", path.string().c_str(), stbi_failure_reason());
  ImageRgba8 img;
  img.width = uint32_t(w);
  img.height = uint32_t(h);
  img.rgba.assign(px, px + size_t(w) * size_t(h) * 4);
  stbi_image_free(px);
  return img;
}

}  // namespace cumulo
