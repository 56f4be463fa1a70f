// libFuzzer target: the TGA slice decoder. Any input must decode or throw cumulo::Error; a decoded
// image must survive encode -> decode unchanged (raw and RLE).
#include <cstdint>
#include <cstdlib>

#include "engine/core/error.h"
#include "modules/clouds/volume/tga.h"

using namespace cumulo;
using namespace cumulo::clouds;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Rgba8Image img;
  try {
    img = decode_tga(std::span<const uint8_t>(data, size), "fuzz.tga", {.max_dimension = 512});
  } catch (const Error&) {
    return 0;
  }
  if (img.rgba.size() != size_t(img.width) * img.height * 4) std::abort();
  for (bool rle : {false, true}) {
    const Rgba8Image back = decode_tga(encode_tga(img, rle), "fuzz roundtrip");
    if (back.width != img.width || back.height != img.height || back.rgba != img.rgba) std::abort();
  }
  return 0;
}
