#include "modules/clouds/volume/volume_file.h"

#include <zstd.h>

#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/hash.h"

namespace cumulo::clouds {

namespace {

constexpr uint8_t kMagic[8] = {'C', 'N', 'V', 'D', 'F', '\r', '\n', 0x1a};
constexpr uint32_t kFlagZstd = 1u;
constexpr uint32_t kKnownFlags = kFlagZstd;
constexpr size_t kFixedHeaderBytes = 96;  // magic .. payload_checksum
constexpr size_t kChannelBytes = 72;      // name[32], semantic[32], f32 min, f32 max
constexpr size_t kNameBytes = 32;
constexpr uint32_t kMaxChannels = 4;

class Writer {
 public:
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    out.insert(out.end(), b, b + n);
  }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void f32(float f) {
    uint32_t v;
    std::memcpy(&v, &f, 4);
    u32(v);
  }
  void name(const std::string& s) {
    char buf[kNameBytes] = {};
    std::memcpy(buf, s.data(), std::min(s.size(), kNameBytes - 1));
    bytes(buf, kNameBytes);
  }
  std::vector<uint8_t> out;
};

// Bounds-checked little-endian reader; every read past the end is a "truncated" error.
class Reader {
 public:
  Reader(std::span<const uint8_t> b, const std::string& name) : b_(b), name_(name) {}
  size_t pos() const { return pos_; }
  const uint8_t* need(size_t n, const char* what) {
    if (n > b_.size() - pos_)
      fail("%s: truncated: %s at byte %zu needs %zu bytes, file has %zu", name_.c_str(), what, pos_, n, b_.size());
    const uint8_t* p = b_.data() + pos_;
    pos_ += n;
    return p;
  }
  uint32_t u32(const char* what) {
    const uint8_t* p = need(4, what);
    return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
  }
  uint64_t u64(const char* what) {
    const uint8_t* p = need(8, what);
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
  }
  float f32(const char* what) {
    uint32_t v = u32(what);
    float f;
    std::memcpy(&f, &v, 4);
    return f;
  }
  std::string name(const char* what) {
    const uint8_t* p = need(kNameBytes, what);
    size_t len = 0;
    while (len < kNameBytes && p[len] != 0) ++len;
    if (len == kNameBytes) fail("%s: %s is not NUL-terminated", name_.c_str(), what);
    for (size_t i = 0; i < len; ++i)
      if (p[i] < 0x20 || p[i] > 0x7e) fail("%s: %s holds a non-printable byte 0x%02x", name_.c_str(), what, p[i]);
    return std::string(reinterpret_cast<const char*>(p), len);
  }

 private:
  std::span<const uint8_t> b_;
  const std::string& name_;
  size_t pos_ = 0;
};

}  // namespace

std::vector<uint8_t> serialize_volume(const Volume& v, const VolumeWriteOptions& opts) {
  v.validate("serialize_volume");
  // Concatenate levels once: the checksum and zstd both want one contiguous payload.
  std::vector<uint8_t> payload;
  payload.reserve(static_cast<size_t>(v.payload_bytes()));
  for (const auto& l : v.levels) payload.insert(payload.end(), l.begin(), l.end());
  const uint64_t checksum = hash64(payload.data(), payload.size());

  std::vector<uint8_t> stored;
  bool compressed = false;
  if (opts.compress && !payload.empty()) {
    stored.resize(ZSTD_compressBound(payload.size()));
    size_t n = ZSTD_compress(stored.data(), stored.size(), payload.data(), payload.size(), opts.zstd_level);
    if (ZSTD_isError(n)) fail("serialize_volume: zstd: %s", ZSTD_getErrorName(n));
    if (n < payload.size()) {
      stored.resize(n);
      compressed = true;
    }
  }
  if (!compressed) stored = std::move(payload);

  Writer w;
  w.bytes(kMagic, sizeof kMagic);
  w.u32(kVolumeFileVersion);
  const size_t header_bytes = kFixedHeaderBytes + kChannelBytes * v.channels.size() + 8 * v.levels.size() + 8;
  w.u32(static_cast<uint32_t>(header_bytes));
  w.u32(compressed ? kFlagZstd : 0u);
  w.u32(static_cast<uint32_t>(v.encoding));
  w.u32(v.size.x);
  w.u32(v.size.y);
  w.u32(v.size.z);
  w.u32(v.mip_count());
  w.u32(static_cast<uint32_t>(v.channels.size()));
  w.f32(v.voxel_size);
  for (int a = 0; a < 3; ++a) w.f32(v.bounds_min[a]);
  for (int a = 0; a < 3; ++a) w.f32(v.bounds_max[a]);
  w.u64(v.payload_bytes());
  w.u64(stored.size());
  w.u64(checksum);
  for (const auto& c : v.channels) {
    w.name(c.name);
    w.name(c.semantic);
    w.f32(c.decode_min);
    w.f32(c.decode_max);
  }
  for (const auto& l : v.levels) w.u64(l.size());
  w.u64(hash64(w.out.data(), w.out.size()));
  w.out.insert(w.out.end(), stored.begin(), stored.end());
  return std::move(w.out);
}

Volume parse_volume(std::span<const uint8_t> bytes, const std::string& name, const VolumeLoadLimits& limits) {
  const char* n = name.c_str();
  Reader r(bytes, name);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    fail("%s: not a cumulo volume file (bad magic; expected \"CNVDF\" header)", n);
  r.need(sizeof kMagic, "magic");
  const uint32_t version = r.u32("version");
  if (version != kVolumeFileVersion)
    fail("%s: unsupported volume file version %u (this build reads version %u)", n, version, kVolumeFileVersion);
  const uint32_t header_bytes = r.u32("header size");
  const uint32_t flags = r.u32("flags");
  const uint32_t encoding = r.u32("encoding");
  glm::uvec3 size;
  size.x = r.u32("size x");
  size.y = r.u32("size y");
  size.z = r.u32("size z");
  const uint32_t mip_count = r.u32("mip count");
  const uint32_t channel_count = r.u32("channel count");
  Volume v;
  v.voxel_size = r.f32("voxel size");
  for (int a = 0; a < 3; ++a) v.bounds_min[a] = r.f32("bounds min");
  for (int a = 0; a < 3; ++a) v.bounds_max[a] = r.f32("bounds max");
  const uint64_t payload_bytes = r.u64("payload size");
  const uint64_t stored_bytes = r.u64("stored size");
  const uint64_t payload_checksum = r.u64("payload checksum");

  // Validate the counts before they size anything.
  if (flags & ~kKnownFlags) fail("%s: unknown flags 0x%x", n, flags);
  if (!is_valid_encoding(encoding)) fail("%s: unknown encoding %u", n, encoding);
  v.encoding = static_cast<VolumeEncoding>(encoding);
  for (int a = 0; a < 3; ++a)
    if (size[a] == 0 || size[a] > limits.max_dimension)
      fail("%s: size %ux%ux%u: axis %c must be 1..%u", n, size.x, size.y, size.z, "xyz"[a], limits.max_dimension);
  v.size = size;
  if (channel_count == 0 || channel_count > kMaxChannels)
    fail("%s: channel count %u (must be 1..%u)", n, channel_count, kMaxChannels);
  if (mip_count == 0 || mip_count > full_mip_count(size))
    fail("%s: mip count %u, size %ux%ux%u allows 1..%u", n, mip_count, size.x, size.y, size.z, full_mip_count(size));
  const uint64_t want_header = kFixedHeaderBytes + uint64_t(kChannelBytes) * channel_count + 8ull * mip_count + 8;
  if (header_bytes != want_header)
    fail("%s: header size field says %u bytes, %u channels and %u mips make %llu", n, header_bytes, channel_count,
         mip_count, static_cast<unsigned long long>(want_header));

  for (uint32_t i = 0; i < channel_count; ++i) {
    VolumeChannel c;
    c.name = r.name("channel name");
    c.semantic = r.name("channel semantic");
    c.decode_min = r.f32("channel decode min");
    c.decode_max = r.f32("channel decode max");
    v.channels.push_back(std::move(c));
  }
  uint64_t want_payload = 0;
  std::vector<uint64_t> level_bytes(mip_count);
  for (uint32_t l = 0; l < mip_count; ++l) {
    level_bytes[l] = r.u64("mip level size");
    const uint64_t want = v.level_bytes(l);
    if (level_bytes[l] != want)
      fail("%s: mip level %u: header says %llu bytes, %s at %ux%ux%u needs %llu", n, l,
           static_cast<unsigned long long>(level_bytes[l]), encoding_name(v.encoding), v.level_size(l).x,
           v.level_size(l).y, v.level_size(l).z, static_cast<unsigned long long>(want));
    want_payload += want;  // each level <= 4096^3 * 8 bytes, at most 13 levels: no overflow
  }
  const size_t checksum_at = r.pos();
  const uint64_t header_checksum = r.u64("header checksum");
  if (hash64(bytes.data(), checksum_at) != header_checksum)
    fail("%s: header checksum mismatch (the header is corrupted)", n);
  if (payload_bytes != want_payload)
    fail("%s: header says %llu payload bytes, its levels need %llu", n, static_cast<unsigned long long>(payload_bytes),
         static_cast<unsigned long long>(want_payload));
  if (payload_bytes > limits.max_payload_bytes)
    fail("%s: payload of %llu bytes is over the limit of %llu", n, static_cast<unsigned long long>(payload_bytes),
         static_cast<unsigned long long>(limits.max_payload_bytes));
  const bool compressed = (flags & kFlagZstd) != 0;
  if (!compressed && stored_bytes != payload_bytes)
    fail("%s: uncompressed payload: stored size %llu differs from payload size %llu", n,
         static_cast<unsigned long long>(stored_bytes), static_cast<unsigned long long>(payload_bytes));
  const uint64_t have = bytes.size() - r.pos();
  if (have < stored_bytes)
    fail("%s: truncated: header says %llu %spayload bytes, file has %llu", n,
         static_cast<unsigned long long>(stored_bytes), compressed ? "compressed " : "",
         static_cast<unsigned long long>(have));
  if (have > stored_bytes)
    fail("%s: %llu bytes of trailing garbage after the payload", n, static_cast<unsigned long long>(have - stored_bytes));
  const uint8_t* stored = r.need(static_cast<size_t>(stored_bytes), "payload");

  std::vector<uint8_t> payload;
  if (compressed) {
    const unsigned long long content = ZSTD_getFrameContentSize(stored, static_cast<size_t>(stored_bytes));
    if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN)
      fail("%s: compressed payload is not a valid zstd frame", n);
    if (content != payload_bytes)
      fail("%s: zstd frame holds %llu bytes, header says %llu", n, content,
           static_cast<unsigned long long>(payload_bytes));
    payload.resize(static_cast<size_t>(payload_bytes));
    const size_t got = ZSTD_decompress(payload.data(), payload.size(), stored, static_cast<size_t>(stored_bytes));
    if (ZSTD_isError(got)) fail("%s: corrupt compressed payload: zstd: %s", n, ZSTD_getErrorName(got));
    if (got != payload_bytes)
      fail("%s: decompressed %zu bytes, header says %llu", n, got, static_cast<unsigned long long>(payload_bytes));
  } else {
    payload.assign(stored, stored + stored_bytes);
  }
  const uint64_t got_checksum = hash64(payload.data(), payload.size());
  if (got_checksum != payload_checksum)
    fail("%s: payload checksum mismatch (stored %016llx, computed %016llx): the file is corrupted", n,
         static_cast<unsigned long long>(payload_checksum), static_cast<unsigned long long>(got_checksum));

  v.levels.resize(mip_count);
  size_t off = 0;
  for (uint32_t l = 0; l < mip_count; ++l) {
    v.levels[l].assign(payload.begin() + static_cast<ptrdiff_t>(off),
                       payload.begin() + static_cast<ptrdiff_t>(off + level_bytes[l]));
    off += static_cast<size_t>(level_bytes[l]);
  }
  // R32F texels are outside numbers like the header's: a NaN or infinite distance would otherwise
  // bake or render an empty cloud with no error.
  if (v.encoding == VolumeEncoding::R32F)
    for (uint32_t l = 0; l < mip_count; ++l)
      for (size_t i = 0; i + 4 <= v.levels[l].size(); i += 4) {
        float f;
        std::memcpy(&f, v.levels[l].data() + i, 4);
        if (!std::isfinite(f)) fail("%s: mip level %u: texel %zu is not a finite number (%g)", n, l, i / 4, double(f));
      }
  v.validate(name);  // bounds, voxel size, channel ranges
  return v;
}

void save_volume(const std::filesystem::path& path, const Volume& v, const VolumeWriteOptions& opts) {
  v.validate(path.string());
  write_file_atomic(path, serialize_volume(v, opts));
}

Volume load_volume(const std::filesystem::path& path, const VolumeLoadLimits& limits) {
  return parse_volume(read_file_bytes(path), path.string(), limits);
}

}  // namespace cumulo::clouds
