#include "modules/clouds/noise/noise_encode.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/parallel.h"

namespace cumulo::clouds {

namespace {

inline uint32_t unorm(float v, uint32_t max) {
  return static_cast<uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * static_cast<float>(max)));
}

// The value a GPU reads back for v stored in `encoding` (round to nearest, as Volume::set_texel).
float quantize(float v, VolumeEncoding encoding) {
  switch (encoding) {
    case VolumeEncoding::R4G4B4A4:
      return static_cast<float>(unorm(v, 15)) / 15.0f;
    case VolumeEncoding::R8:
    case VolumeEncoding::RG8:
    case VolumeEncoding::RGBA8:
      return static_cast<float>(unorm(v, 255)) / 255.0f;
    case VolumeEncoding::R16:
    case VolumeEncoding::RGBA16:
      return static_cast<float>(unorm(v, 65535)) / 65535.0f;
    case VolumeEncoding::R32F:
      return v;
    default:  // block-compressed encodings: not for noise
      break;
  }
  fail("noise textures cannot be stored as %s", encoding_name(encoding));
}

inline float lerp(float a, float b, float t) { return a + (b - a) * t; }
inline float saturate(float v) { return std::clamp(v, 0.0f, 1.0f); }

}  // namespace

uint16_t pack_r4g4b4a4(float r, float g, float b, float a) {
  return static_cast<uint16_t>((unorm(r, 15) << 12) | (unorm(g, 15) << 8) | (unorm(b, 15) << 4) | unorm(a, 15));
}

float unpack_r4g4b4a4(uint16_t word, int channel) {
  return static_cast<float>((word >> (12 - 4 * channel)) & 15u) / 15.0f;
}

Volume noise_to_volume(const NoiseTexture& tex, VolumeEncoding encoding, const std::vector<NoiseChannelInfo>& channels,
                       float tile_metres) {
  if (channels.size() != static_cast<size_t>(tex.channels))
    fail("%s: %zu channel descriptions for %d channels", tex.name.c_str(), channels.size(), tex.channels);
  if (static_cast<uint32_t>(tex.channels) > encoding_components(encoding))
    fail("%s: %d channels do not fit %s", tex.name.c_str(), tex.channels, encoding_name(encoding));
  std::vector<VolumeChannel> vc;
  for (const NoiseChannelInfo& c : channels) vc.push_back({c.name, std::string(kNoise), c.decode_min, c.decode_max});
  glm::uvec3 size(tex.width, tex.height, tex.depth);
  Volume v = Volume::create(size, tile_metres / static_cast<float>(tex.width), encoding, std::move(vc),
                            static_cast<uint32_t>(tex.levels()));
  // A 2D texture is a one-texel-thick slab; bounds follow the texel grid.
  v.bounds_min = glm::vec3(0.0f);
  v.bounds_max = glm::vec3(size) * v.voxel_size;
  if (v.mip_count() != static_cast<uint32_t>(tex.levels()))
    fail("%s: %d mip levels, the volume expects %u", tex.name.c_str(), tex.levels(), v.mip_count());
  for (int level = 0; level < tex.levels(); ++level) {
    const int w = tex.level_width(level), h = tex.level_height(level), d = tex.level_depth(level);
    parallel_for(static_cast<size_t>(d), [&](size_t z0, size_t z1) {
      for (size_t z = z0; z < z1; ++z)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            for (int c = 0; c < tex.channels; ++c)
              v.set_texel(x, y, static_cast<uint32_t>(z), c, tex.at(level, x, y, static_cast<int>(z), c), level);
    });
  }
  return v;
}

std::vector<ChannelError> quantization_error(const NoiseTexture& tex, VolumeEncoding encoding, int level) {
  std::vector<ChannelError> out(tex.channels);
  const std::vector<float>& data = tex.mips.at(level);
  const size_t n = tex.level_texels(level);
  for (int c = 0; c < tex.channels; ++c) {
    double sum2 = 0.0, max_abs = 0.0;
    for (size_t i = 0; i < n; ++i) {
      float v = data[i * tex.channels + c];
      double e = std::abs(static_cast<double>(quantize(v, encoding)) - v);
      sum2 += e * e;
      max_abs = std::max(max_abs, e);
    }
    out[c].max_abs = max_abs;
    out[c].rmse = std::sqrt(sum2 / static_cast<double>(n));
    out[c].psnr_db = out[c].rmse > 0.0 ? 20.0 * std::log10(1.0 / out[c].rmse) : 999.0;
  }
  return out;
}

float value_erosion(float profile, float erosion) {
  // remap(profile, erosion, 1, 0, 1), saturated; erosion == 1 erodes everything.
  if (erosion >= 1.0f) return 0.0f;
  return saturate((profile - erosion) / (1.0f - erosion));
}

float uprez_density(const float noise[4], float profile, float type, float density_scale) {
  float wispy = lerp(noise[0], noise[1], profile);
  float billowy = lerp(noise[2] * 0.3f, noise[3] * 0.3f, std::pow(profile, 0.25f));
  float composite = lerp(wispy, billowy, type);
  float density = value_erosion(profile, composite) * density_scale;
  constexpr float kEpsilon = 1e-4f;
  float sharpen = lerp(0.3f, 0.6f, std::max(kEpsilon, std::pow(saturate(density_scale), 4.0f)));
  return density > 0.0f ? std::pow(density, sharpen) : 0.0f;
}

UprezError uprez_error(const NoiseTexture& tex, VolumeEncoding encoding) {
  if (tex.channels != 4) fail("%s: the up-rez needs 4 noise channels, got %d", tex.name.c_str(), tex.channels);
  const int w = tex.width, h = tex.height, d = tex.depth;
  struct Acc {
    double sum = 0, sum2 = 0, max = 0, ref = 0;
    size_t above = 0;
  };
  std::vector<Acc> per_slice(d);
  parallel_for(static_cast<size_t>(d), [&](size_t z0, size_t z1) {
    for (size_t z = z0; z < z1; ++z) {
      Acc& a = per_slice[z];
      float scale = lerp(0.25f, 1.0f, (static_cast<float>(z) + 0.5f) / static_cast<float>(d));
      for (int y = 0; y < h; ++y) {
        float type = (static_cast<float>(y) + 0.5f) / static_cast<float>(h);
        for (int x = 0; x < w; ++x) {
          float profile = (static_cast<float>(x) + 0.5f) / static_cast<float>(w);
          float ref[4], q[4];
          for (int c = 0; c < 4; ++c) {
            ref[c] = tex.at(0, x, y, static_cast<int>(z), c);
            q[c] = quantize(ref[c], encoding);
          }
          double r = uprez_density(ref, profile, type, scale);
          double e = std::abs(static_cast<double>(uprez_density(q, profile, type, scale)) - r);
          a.sum += e;
          a.sum2 += e * e;
          a.max = std::max(a.max, e);
          a.ref += r;
          a.above += e > 0.05;
        }
      }
    }
  });
  Acc total;
  for (const Acc& a : per_slice) {
    total.sum += a.sum;
    total.sum2 += a.sum2;
    total.max = std::max(total.max, a.max);
    total.ref += a.ref;
    total.above += a.above;
  }
  double n = static_cast<double>(w) * h * d;
  return {total.sum / n, total.max, std::sqrt(total.sum2 / n), static_cast<double>(total.above) / n, total.ref / n};
}

}  // namespace cumulo::clouds
