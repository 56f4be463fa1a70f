#include "modules/clouds/volume/volume.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "modules/clouds/volume/bc1.h"

namespace cumulo::clouds {

namespace {

struct EncodingInfo {
  VolumeEncoding e;
  const char* name;
  uint32_t components;
  uint32_t texel_bytes;  // 0 for block encodings
  uint32_t block_bytes;  // 0 for texel encodings
};

constexpr EncodingInfo kEncodings[] = {
    {VolumeEncoding::R8, "r8", 1, 1, 0},           {VolumeEncoding::RG8, "rg8", 2, 2, 0},
    {VolumeEncoding::RGBA8, "rgba8", 4, 4, 0},     {VolumeEncoding::R16, "r16", 1, 2, 0},
    {VolumeEncoding::RGBA16, "rgba16", 4, 8, 0},   {VolumeEncoding::R32F, "r32f", 1, 4, 0},
    {VolumeEncoding::R4G4B4A4, "r4g4b4a4", 4, 2, 0}, {VolumeEncoding::BC1, "bc1", 4, 0, 8},
    {VolumeEncoding::BC4, "bc4", 1, 0, 8},         {VolumeEncoding::BC7, "bc7", 4, 0, 16},
};

const EncodingInfo& info(VolumeEncoding e) {
  for (const auto& i : kEncodings)
    if (i.e == e) return i;
  fail("invalid volume encoding %u", static_cast<unsigned>(e));
}

uint16_t load16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
void store16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}

uint32_t unorm(float v, uint32_t max) {
  if (!(v > 0.0f)) return 0;  // also catches NaN
  if (v >= 1.0f) return max;
  return static_cast<uint32_t>(std::lround(v * static_cast<float>(max)));
}

}  // namespace

const char* encoding_name(VolumeEncoding e) {
  for (const auto& i : kEncodings)
    if (i.e == e) return i.name;
  return "invalid";
}

bool parse_encoding(std::string_view name, VolumeEncoding* out) {
  for (const auto& i : kEncodings)
    if (name == i.name) {
      *out = i.e;
      return true;
    }
  return false;
}

bool is_valid_encoding(uint32_t value) {
  for (const auto& i : kEncodings)
    if (static_cast<uint32_t>(i.e) == value) return true;
  return false;
}

uint32_t encoding_components(VolumeEncoding e) { return info(e).components; }
bool is_block_encoding(VolumeEncoding e) { return info(e).block_bytes != 0; }
uint32_t encoding_texel_bytes(VolumeEncoding e) { return info(e).texel_bytes; }
uint32_t encoding_block_bytes(VolumeEncoding e) { return info(e).block_bytes; }

uint64_t encoded_level_bytes(VolumeEncoding e, glm::uvec3 s) {
  // Each factor is < 2^32, so a product of two fits in 64 bits; the third is checked.
  uint64_t per_slice;
  if (is_block_encoding(e))
    per_slice = uint64_t(bc1_blocks(s.x)) * bc1_blocks(s.y) * info(e).block_bytes;  // < 2^30 * 2^30 * 16
  else
    per_slice = uint64_t(s.x) * s.y;
  uint64_t slices = s.z;
  if (slices != 0 && per_slice > UINT64_MAX / slices) return UINT64_MAX;
  uint64_t total = per_slice * slices;
  if (!is_block_encoding(e)) {
    uint64_t tb = info(e).texel_bytes;
    if (total > UINT64_MAX / tb) return UINT64_MAX;
    total *= tb;
  }
  return total;
}

glm::uvec3 mip_level_size(glm::uvec3 base, uint32_t level) {
  auto half = [&](uint32_t v) { return level >= 32 ? 1u : std::max(1u, v >> level); };
  return {half(base.x), half(base.y), half(base.z)};
}

uint32_t full_mip_count(glm::uvec3 base) {
  uint32_t m = std::max({base.x, base.y, base.z, 1u});
  uint32_t n = 1;
  while (m > 1) {
    m >>= 1;
    ++n;
  }
  return n;
}

Volume Volume::create(glm::uvec3 size, float voxel_size, VolumeEncoding encoding, std::vector<VolumeChannel> channels,
                      uint32_t mip_count) {
  Volume v;
  v.size = size;
  v.voxel_size = voxel_size;
  v.bounds_min = glm::vec3(0.0f);
  v.bounds_max = glm::vec3(size) * voxel_size;
  v.encoding = encoding;
  v.channels = std::move(channels);
  mip_count = std::max(1u, mip_count);
  v.levels.resize(mip_count);
  for (uint32_t l = 0; l < mip_count; ++l) {
    uint64_t bytes = v.level_bytes(l);
    if (bytes > (uint64_t(1) << 40)) fail("volume %ux%ux%u %s: too large", size.x, size.y, size.z, encoding_name(encoding));
    v.levels[l].assign(static_cast<size_t>(bytes), 0);
  }
  return v;
}

uint64_t Volume::payload_bytes() const {
  uint64_t total = 0;
  for (const auto& l : levels) total += l.size();
  return total;
}

int Volume::find_channel(std::string_view semantic) const {
  for (size_t i = 0; i < channels.size(); ++i)
    if (channels[i].semantic == semantic) return static_cast<int>(i);
  return -1;
}

uint32_t Volume::channel(std::string_view semantic, std::string_view what) const {
  int i = find_channel(semantic);
  if (i < 0) {
    std::string have;
    for (const auto& c : channels) have += (have.empty() ? "" : ", ") + c.semantic;
    fail("%.*s: no channel with semantic '%.*s' (has: %s)", int(what.size()), what.data(), int(semantic.size()),
         semantic.data(), have.empty() ? "none" : have.c_str());
  }
  return static_cast<uint32_t>(i);
}

float Volume::texel(uint32_t x, uint32_t y, uint32_t z, uint32_t c, uint32_t level) const {
  const glm::uvec3 s = level_size(level);
  const std::vector<uint8_t>& d = levels.at(level);
  if (x >= s.x || y >= s.y || z >= s.z || c >= encoding_components(encoding))
    fail("volume texel (%u,%u,%u) component %u out of range at level %u", x, y, z, c, level);
  if (is_block_encoding(encoding)) {
    size_t block = ((size_t(z) * bc1_blocks(s.y) + y / 4) * bc1_blocks(s.x) + x / 4) * encoding_block_bytes(encoding);
    if (encoding == VolumeEncoding::BC1) return bc1_decode_texel(d.data() + block, x % 4, y % 4)[static_cast<int>(c)];
    if (encoding == VolumeEncoding::BC4) return bc4_decode_texel(d.data() + block, x % 4, y % 4);
    fail("volume texel: no CPU decode for %s", encoding_name(encoding));
  }
  const size_t i = (size_t(z) * s.y + y) * s.x + x;
  switch (encoding) {
    case VolumeEncoding::R8:
    case VolumeEncoding::RG8:
    case VolumeEncoding::RGBA8: {
      uint32_t n = info(encoding).components;
      return d[i * n + c] / 255.0f;
    }
    case VolumeEncoding::R16:
      return load16(&d[i * 2]) / 65535.0f;
    case VolumeEncoding::RGBA16:
      return load16(&d[i * 8 + c * 2]) / 65535.0f;
    case VolumeEncoding::R32F: {
      float f;
      std::memcpy(&f, &d[i * 4], 4);
      return f;
    }
    case VolumeEncoding::R4G4B4A4: {
      uint16_t w = load16(&d[i * 2]);
      return static_cast<float>((w >> (12 - 4 * c)) & 15u) / 15.0f;
    }
    default:
      break;
  }
  return 0.0f;
}

float Volume::decoded(uint32_t x, uint32_t y, uint32_t z, uint32_t c, uint32_t level) const {
  float t = texel(x, y, z, c, level);
  if (encoding == VolumeEncoding::R32F || c >= channels.size()) return t;
  const VolumeChannel& ch = channels[c];
  return ch.decode_min + t * (ch.decode_max - ch.decode_min);
}

void Volume::set_texel(uint32_t x, uint32_t y, uint32_t z, uint32_t c, float value, uint32_t level) {
  const glm::uvec3 s = level_size(level);
  std::vector<uint8_t>& d = levels.at(level);
  if (x >= s.x || y >= s.y || z >= s.z || c >= encoding_components(encoding))
    fail("volume texel (%u,%u,%u) component %u out of range at level %u", x, y, z, c, level);
  const size_t i = (size_t(z) * s.y + y) * s.x + x;
  switch (encoding) {
    case VolumeEncoding::R8:
    case VolumeEncoding::RG8:
    case VolumeEncoding::RGBA8:
      d[i * info(encoding).components + c] = static_cast<uint8_t>(unorm(value, 255));
      return;
    case VolumeEncoding::R16:
      store16(&d[i * 2], static_cast<uint16_t>(unorm(value, 65535)));
      return;
    case VolumeEncoding::RGBA16:
      store16(&d[i * 8 + c * 2], static_cast<uint16_t>(unorm(value, 65535)));
      return;
    case VolumeEncoding::R32F:
      std::memcpy(&d[i * 4], &value, 4);
      return;
    case VolumeEncoding::R4G4B4A4: {
      uint16_t w = load16(&d[i * 2]);
      uint32_t shift = 12 - 4 * c;
      w = static_cast<uint16_t>((w & ~(15u << shift)) | (unorm(value, 15) << shift));
      store16(&d[i * 2], w);
      return;
    }
    default:
      break;
  }
  fail("set_texel: %s volumes are written block by block by their encoder", encoding_name(encoding));
}

void Volume::set_decoded(uint32_t x, uint32_t y, uint32_t z, uint32_t c, float value, uint32_t level) {
  if (encoding == VolumeEncoding::R32F || c >= channels.size()) return set_texel(x, y, z, c, value, level);
  const VolumeChannel& ch = channels[c];
  float range = ch.decode_max - ch.decode_min;
  set_texel(x, y, z, c, range != 0.0f ? (value - ch.decode_min) / range : 0.0f, level);
}

void Volume::validate(std::string_view what_sv) const {
  const std::string what(what_sv);
  const char* w = what.c_str();
  if (!is_valid_encoding(static_cast<uint32_t>(encoding)))
    fail("%s: invalid encoding %u", w, static_cast<unsigned>(encoding));
  if (size.x == 0 || size.y == 0 || size.z == 0) fail("%s: empty size %ux%ux%u", w, size.x, size.y, size.z);
  if (!std::isfinite(voxel_size) || voxel_size <= 0.0f) fail("%s: voxel size %g is not a positive number", w, voxel_size);
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(bounds_min[a]) || !std::isfinite(bounds_max[a]) || !(bounds_max[a] > bounds_min[a]))
      fail("%s: world bounds axis %c: min %g, max %g (need finite min < max)", w, "xyz"[a], bounds_min[a],
           bounds_max[a]);
  const uint32_t comps = encoding_components(encoding);
  if (channels.empty() || channels.size() > comps)
    fail("%s: %zu channels, encoding %s holds 1..%u", w, channels.size(), encoding_name(encoding), comps);
  for (size_t i = 0; i < channels.size(); ++i) {
    const VolumeChannel& c = channels[i];
    if (c.name.size() > 31 || c.semantic.size() > 31)
      fail("%s: channel %zu: name/semantic longer than 31 bytes", w, i);
    if (!std::isfinite(c.decode_min) || !std::isfinite(c.decode_max) || c.decode_min == c.decode_max)
      fail("%s: channel %zu ('%s'): decode range %g..%g is not a finite, non-empty range", w, i, c.semantic.c_str(),
           c.decode_min, c.decode_max);
  }
  const uint32_t max_mips = full_mip_count(size);
  if (levels.empty() || levels.size() > max_mips)
    fail("%s: %zu mip levels, size %ux%ux%u allows 1..%u", w, levels.size(), size.x, size.y, size.z, max_mips);
  for (uint32_t l = 0; l < mip_count(); ++l) {
    uint64_t want = level_bytes(l);
    if (levels[l].size() != want)
      fail("%s: mip level %u holds %zu bytes, %s at %ux%ux%u needs %llu", w, l, levels[l].size(),
           encoding_name(encoding), level_size(l).x, level_size(l).y, level_size(l).z,
           static_cast<unsigned long long>(want));
  }
}

void generate_mips(Volume& v, uint32_t mip_count, bool wrap) {
  if (is_block_encoding(v.encoding)) fail("generate_mips: %s volumes must be mipped before encoding", encoding_name(v.encoding));
  const uint32_t full = full_mip_count(v.size);
  if (mip_count == 0 || mip_count > full) mip_count = full;
  v.levels.resize(1);
  const uint32_t comps = encoding_components(v.encoding);
  for (uint32_t l = 1; l < mip_count; ++l) {
    const glm::uvec3 src = v.level_size(l - 1), dst = v.level_size(l);
    v.levels.emplace_back(static_cast<size_t>(v.level_bytes(l)), 0);
    // Each destination texel averages its 2x2x2 source footprint; an axis that did not halve
    // (already 1) uses 1 sample, an odd source axis folds the last texel in via clamp or wrap.
    auto src_index = [&](uint32_t d, uint32_t k, uint32_t n_src, uint32_t n_dst) -> uint32_t {
      if (n_src == n_dst) return d;
      uint32_t s = 2 * d + k;
      if (s >= n_src) s = wrap ? s % n_src : n_src - 1;
      return s;
    };
    for (uint32_t z = 0; z < dst.z; ++z)
      for (uint32_t y = 0; y < dst.y; ++y)
        for (uint32_t x = 0; x < dst.x; ++x)
          for (uint32_t c = 0; c < comps; ++c) {
            float sum = 0.0f;
            int n = 0;
            for (uint32_t kz = 0; kz < (src.z == dst.z ? 1u : 2u); ++kz)
              for (uint32_t ky = 0; ky < (src.y == dst.y ? 1u : 2u); ++ky)
                for (uint32_t kx = 0; kx < (src.x == dst.x ? 1u : 2u); ++kx) {
                  sum += v.texel(src_index(x, kx, src.x, dst.x), src_index(y, ky, src.y, dst.y),
                                 src_index(z, kz, src.z, dst.z), c, l - 1);
                  ++n;
                }
            v.set_texel(x, y, z, c, sum / static_cast<float>(n), l);
          }
  }
}

float bc4_decode_texel(const uint8_t* block, uint32_t tx, uint32_t ty) {
  const float r0 = block[0] / 255.0f, r1 = block[1] / 255.0f;
  uint64_t bits = 0;
  for (int i = 7; i >= 2; --i) bits = (bits << 8) | block[i];
  const uint32_t idx = static_cast<uint32_t>(bits >> (3 * (ty * 4 + tx))) & 7u;
  if (idx == 0) return r0;
  if (idx == 1) return r1;
  if (block[0] > block[1]) return ((8 - idx) * r0 + (idx - 1) * r1) / 7.0f;
  if (idx == 6) return 0.0f;
  if (idx == 7) return 1.0f;
  return ((6 - idx) * r0 + (idx - 1) * r1) / 5.0f;
}

float sample_trilinear(const Volume& v, glm::vec3 uvw, uint32_t c, bool repeat) {
  const glm::ivec3 n(v.size);
  const glm::vec3 p = uvw * glm::vec3(n) - 0.5f;
  const glm::vec3 f0 = glm::floor(p);
  const glm::vec3 w = p - f0;
  const glm::ivec3 i0(f0);
  auto coord = [&](int i, int size) {
    if (repeat) return ((i % size) + size) % size;
    return std::clamp(i, 0, size - 1);
  };
  float out = 0.0f;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 o((k & 1), (k >> 1) & 1, (k >> 2) & 1);
    const float weight = (o.x ? w.x : 1.0f - w.x) * (o.y ? w.y : 1.0f - w.y) * (o.z ? w.z : 1.0f - w.z);
    if (weight == 0.0f) continue;
    out += weight * v.texel(uint32_t(coord(i0.x + o.x, n.x)), uint32_t(coord(i0.y + o.y, n.y)),
                            uint32_t(coord(i0.z + o.z, n.z)), c);
  }
  return out;
}

}  // namespace cumulo::clouds
