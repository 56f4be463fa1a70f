#pragma once
// A 16-bit grey PNG writer for the tests (the engine's encoder writes 8 bits only): stored (uncompressed) deflate
// blocks, so it needs no zlib.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/file_io.h"

namespace cumulo::test {

inline uint32_t png_crc(const uint8_t* p, size_t n, uint32_t c = 0xffffffffu) {
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c;
}

inline void write_grey_png16(const std::filesystem::path& path, const std::vector<uint16_t>& px, uint32_t w,
                             uint32_t h) {
  std::vector<uint8_t> raw;
  for (uint32_t y = 0; y < h; ++y) {
    raw.push_back(0);  // filter: none
    for (uint32_t x = 0; x < w; ++x) {
      raw.push_back(uint8_t(px[size_t(y) * w + x] >> 8));
      raw.push_back(uint8_t(px[size_t(y) * w + x] & 0xff));
    }
  }
  std::vector<uint8_t> z{0x78, 0x01};
  for (size_t at = 0; at < raw.size() || at == 0;) {
    const size_t len = std::min<size_t>(65535, raw.size() - at);
    const bool last = at + len == raw.size();
    z.push_back(last ? 1 : 0);
    z.push_back(uint8_t(len & 0xff));
    z.push_back(uint8_t(len >> 8));
    z.push_back(uint8_t(~len & 0xff));
    z.push_back(uint8_t((~len >> 8) & 0xff));
    z.insert(z.end(), raw.begin() + long(at), raw.begin() + long(at + len));
    at += len;
    if (last) break;
  }
  uint32_t a = 1, b = 0;
  for (uint8_t c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  const uint32_t adler = (b << 16) | a;
  for (int s = 24; s >= 0; s -= 8) z.push_back(uint8_t(adler >> s));

  std::vector<uint8_t> out{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  auto be32 = [&](uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t(v >> s));
  };
  auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
    be32(uint32_t(data.size()));
    const size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    be32(png_crc(&out[start], out.size() - start) ^ 0xffffffffu);
  };
  std::vector<uint8_t> ihdr;
  for (uint32_t v : {w, h})
    for (int s = 24; s >= 0; s -= 8) ihdr.push_back(uint8_t(v >> s));
  ihdr.insert(ihdr.end(), {16, 0, 0, 0, 0});  // 16 bits, grey, deflate, no filter method, no interlace
  chunk("IHDR", ihdr);
  chunk("IDAT", z);
  chunk("IEND", {});
  write_file_atomic(path, out);
}

}  // namespace cumulo::test
