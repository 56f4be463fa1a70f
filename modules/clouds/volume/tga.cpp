#include "modules/clouds/volume/tga.h"

#include <array>
#include <cstring>
#include <fstream>

#include "engine/core/error.h"
#include "engine/core/file_io.h"

namespace cumulo::clouds {

namespace {
constexpr size_t kHeaderBytes = 18;
uint16_t le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
}  // namespace

namespace {

// What the header says and where the pixels start, checked against the file's size before anything is allocated:
// the decoder and the slice budget (peek_tga_size) refuse the same files with the same message.
struct TgaHeader {
  uint32_t width = 0, height = 0, bpp = 0, type = 0, descriptor = 0;
  bool rle = false, gray = false;
  size_t pos = 0;  // the first pixel byte
};

TgaHeader parse_header(const uint8_t* h, size_t file_bytes, const char* n, const TgaLimits& limits) {
  if (file_bytes < kHeaderBytes) fail("%s: truncated TGA: %zu bytes, the header alone is 18", n, file_bytes);
  TgaHeader t;
  const uint32_t id_length = h[0], cmap_type = h[1];
  const uint32_t cmap_length = le16(h + 5), cmap_entry_bits = h[7];
  t.type = h[2];
  t.width = le16(h + 12), t.height = le16(h + 14), t.bpp = h[16], t.descriptor = h[17];
  t.rle = t.type == 10 || t.type == 11;
  t.gray = t.type == 3 || t.type == 11;
  if (t.type != 2 && t.type != 3 && t.type != 10 && t.type != 11)
    fail("%s: unsupported TGA image type %u (need 2/10 truecolor or 3/11 grayscale)", n, t.type);
  if (cmap_type > 1) fail("%s: bad TGA colour map type %u", n, cmap_type);
  if (t.gray ? t.bpp != 8 : (t.bpp != 24 && t.bpp != 32))
    fail("%s: unsupported TGA pixel depth %u for image type %u (need %s)", n, t.bpp, t.type, t.gray ? "8" : "24 or 32");
  if (t.width == 0 || t.height == 0 || t.width > limits.max_dimension || t.height > limits.max_dimension)
    fail("%s: TGA size %ux%u (each side must be 1..%u)", n, t.width, t.height, limits.max_dimension);
  if (t.descriptor & 0xc0) fail("%s: interleaved TGA (descriptor 0x%02x) is not supported", n, t.descriptor);

  t.pos = kHeaderBytes + id_length;
  if (cmap_type == 1) t.pos += size_t(cmap_length) * ((cmap_entry_bits + 7) / 8);  // unused by truecolor
  if (t.pos > file_bytes) fail("%s: truncated TGA: image ID / colour map run past the end of the file", n);
  const uint32_t pixel_bytes = t.bpp / 8;
  const size_t count = size_t(t.width) * t.height;
  // Refuse before allocating: raw data needs every pixel, RLE at least one packet per 128 pixels.
  const size_t min_bytes = t.rle ? (count + 127) / 128 * (1 + pixel_bytes) : count * pixel_bytes;
  if (file_bytes - t.pos < min_bytes)
    fail("%s: truncated TGA: %ux%u at %u bits needs %s%zu pixel bytes, file has %zu", n, t.width, t.height, t.bpp,
         t.rle ? "at least " : "", min_bytes, file_bytes - t.pos);
  return t;
}

}  // namespace

Rgba8Image decode_tga(std::span<const uint8_t> bytes, const std::string& name, const TgaLimits& limits) {
  const char* n = name.c_str();
  const TgaHeader t = parse_header(bytes.data(), bytes.size(), n, limits);
  const uint32_t width = t.width, height = t.height, bpp = t.bpp, descriptor = t.descriptor;
  const bool rle = t.rle, gray = t.gray;
  size_t pos = t.pos;
  const uint32_t pixel_bytes = bpp / 8;
  const size_t count = size_t(width) * height;
  std::vector<uint8_t> src(count * pixel_bytes);  // file order, file pixel layout
  if (!rle) {
    std::memcpy(src.data(), bytes.data() + pos, src.size());
  } else {
    // Packets may cross rows (common in the wild); they may not run past the image.
    size_t done = 0;
    while (done < count) {
      if (pos >= bytes.size())
        fail("%s: truncated TGA: RLE data ends after %zu of %zu pixels", n, done, count);
      const uint8_t packet = bytes[pos++];
      const size_t run = (packet & 0x7fu) + 1u;
      if (run > count - done)
        fail("%s: bad TGA RLE packet at byte %zu: %zu pixels overrun the image (%zu left)", n, pos - 1, run,
             count - done);
      if (packet & 0x80u) {
        if (bytes.size() - pos < pixel_bytes) fail("%s: truncated TGA: RLE run at byte %zu", n, pos - 1);
        for (size_t i = 0; i < run; ++i) std::memcpy(&src[(done + i) * pixel_bytes], &bytes[pos], pixel_bytes);
        pos += pixel_bytes;
      } else {
        if (bytes.size() - pos < run * pixel_bytes) fail("%s: truncated TGA: raw packet at byte %zu", n, pos - 1);
        std::memcpy(&src[done * pixel_bytes], &bytes[pos], run * pixel_bytes);
        pos += run * pixel_bytes;
      }
      done += run;
    }
  }

  Rgba8Image img;
  img.width = width;
  img.height = height;
  img.rgba.resize(count * 4);
  const bool top_down = descriptor & 0x20, right_to_left = descriptor & 0x10;
  for (uint32_t fy = 0; fy < height; ++fy) {
    const uint32_t y = top_down ? fy : height - 1 - fy;
    for (uint32_t fx = 0; fx < width; ++fx) {
      const uint32_t x = right_to_left ? width - 1 - fx : fx;
      const uint8_t* s = &src[(size_t(fy) * width + fx) * pixel_bytes];
      uint8_t* d = &img.rgba[(size_t(y) * width + x) * 4];
      if (gray) {
        d[0] = d[1] = d[2] = s[0];
        d[3] = 255;
      } else {  // BGR(A)
        d[0] = s[2];
        d[1] = s[1];
        d[2] = s[0];
        d[3] = pixel_bytes == 4 ? s[3] : 255;
      }
    }
  }
  return img;
}

Rgba8Image load_tga(const std::filesystem::path& path, const TgaLimits& limits) {
  return decode_tga(read_file_bytes(path), path.string(), limits);
}

std::pair<uint32_t, uint32_t> peek_tga_size(const std::filesystem::path& path, const TgaLimits& limits) {
  const std::string name = path.string();
  std::error_code ec;
  const uintmax_t file_bytes = std::filesystem::file_size(path, ec);
  if (ec) fail("%s: cannot read: %s", name.c_str(), ec.message().c_str());
  std::ifstream in(path, std::ios::binary);
  uint8_t h[kHeaderBytes] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (!in && !in.eof()) fail("%s: cannot read", name.c_str());
  const TgaHeader t = parse_header(h, size_t(file_bytes), name.c_str(), limits);
  return {t.width, t.height};
}

std::vector<uint8_t> encode_tga(const Rgba8Image& image, bool rle) {
  if (image.width == 0 || image.height == 0 || image.width > 65535 || image.height > 65535 ||
      image.rgba.size() != size_t(image.width) * image.height * 4)
    fail("encode_tga: bad image %ux%u with %zu bytes", image.width, image.height, image.rgba.size());
  std::vector<uint8_t> out(kHeaderBytes, 0);
  out[2] = rle ? 10 : 2;
  out[12] = static_cast<uint8_t>(image.width), out[13] = static_cast<uint8_t>(image.width >> 8);
  out[14] = static_cast<uint8_t>(image.height), out[15] = static_cast<uint8_t>(image.height >> 8);
  out[16] = 32;
  out[17] = 0x20 | 8;  // top-left origin, 8 alpha bits
  auto bgra = [&](size_t i) {
    const uint8_t* p = &image.rgba[i * 4];
    return std::array<uint8_t, 4>{p[2], p[1], p[0], p[3]};
  };
  const size_t count = size_t(image.width) * image.height;
  if (!rle) {
    for (size_t i = 0; i < count; ++i) {
      auto px = bgra(i);
      out.insert(out.end(), px.begin(), px.end());
    }
    return out;
  }
  // RLE packets stay within a row, as the TGA 2.0 spec recommends.
  for (uint32_t y = 0; y < image.height; ++y) {
    const size_t row = size_t(y) * image.width;
    uint32_t x = 0;
    while (x < image.width) {
      uint32_t run = 1;
      while (x + run < image.width && run < 128 && bgra(row + x + run) == bgra(row + x)) ++run;
      if (run > 1) {
        out.push_back(static_cast<uint8_t>(0x80 | (run - 1)));
        auto px = bgra(row + x);
        out.insert(out.end(), px.begin(), px.end());
        x += run;
        continue;
      }
      uint32_t raw = 1;  // extend until the next pair of equal pixels
      while (x + raw < image.width && raw < 128 &&
             !(x + raw + 1 < image.width && bgra(row + x + raw) == bgra(row + x + raw + 1)))
        ++raw;
      out.push_back(static_cast<uint8_t>(raw - 1));
      for (uint32_t i = 0; i < raw; ++i) {
        auto px = bgra(row + x + i);
        out.insert(out.end(), px.begin(), px.end());
      }
      x += raw;
    }
  }
  return out;
}

}  // namespace cumulo::clouds
