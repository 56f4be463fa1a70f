#include "modules/clouds/noise/noise_textures.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/parallel.h"
#include "engine/core/progress.h"

namespace cumulo::clouds {

namespace {

bool is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }

void check_size(const char* what, int size) {
  if (!is_pow2(size) || size < 4 || size > 1024)
    fail("%s: size %d must be a power of two in 4..1024 (the mip chain halves it down to 1)", what, size);
}

// Texel centre in tile space [0, 1).
inline float tc(int i, int n) { return (static_cast<float>(i) + 0.5f) / static_cast<float>(n); }

NoiseTexture make_texture(std::string name, int w, int h, int d, int channels) {
  NoiseTexture t;
  t.name = std::move(name);
  t.width = w;
  t.height = h;
  t.depth = d;
  t.channels = channels;
  return t;
}

}  // namespace

void fill_texture(NoiseTexture& tex, const TexelFn& fn, Progress* progress) {
  const int w = tex.width, h = tex.height, d = tex.depth, ch = tex.channels;
  tex.mips.assign(1, std::vector<float>(static_cast<size_t>(w) * h * d * ch));
  float* data = tex.mips[0].data();
  parallel_for(static_cast<size_t>(h) * d, [&](size_t begin, size_t end) {
    for (size_t row = begin; row < end; ++row) {
      int y = static_cast<int>(row % h), z = static_cast<int>(row / h);
      float* out = data + row * w * ch;
      for (int x = 0; x < w; ++x) fn(x, y, z, out + static_cast<size_t>(x) * ch);
      if (progress) progress->add(w);
    }
  });
}

void normalize_channels(NoiseTexture& tex) {
  std::vector<float>& v = tex.mips.at(0);
  const int ch = tex.channels;
  for (int c = 0; c < ch; ++c) {
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
    for (size_t i = c; i < v.size(); i += ch) {
      lo = std::min(lo, v[i]);
      hi = std::max(hi, v[i]);
    }
    float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
    for (size_t i = c; i < v.size(); i += ch) v[i] = std::clamp((v[i] - lo) * scale, 0.0f, 1.0f);
  }
}

void build_mips(NoiseTexture& tex) {
  if (!is_pow2(tex.width) || !is_pow2(tex.height) || !is_pow2(tex.depth))
    fail("%s: mips need power-of-two sizes, got %dx%dx%d", tex.name.c_str(), tex.width, tex.height, tex.depth);
  tex.mips.resize(1);
  const int ch = tex.channels;
  for (int level = 1;; ++level) {
    int pw = tex.level_width(level - 1), ph = tex.level_height(level - 1), pd = tex.level_depth(level - 1);
    if (pw == 1 && ph == 1 && pd == 1) break;
    int w = tex.level_width(level), h = tex.level_height(level), d = tex.level_depth(level);
    // A dimension already at 1 is not halved (2D textures keep depth 1): average 1 texel there.
    int sx = pw > 1 ? 2 : 1, sy = ph > 1 ? 2 : 1, sz = pd > 1 ? 2 : 1;
    float norm = 1.0f / static_cast<float>(sx * sy * sz);
    const std::vector<float>& src = tex.mips[level - 1];
    std::vector<float> dst(static_cast<size_t>(w) * h * d * ch, 0.0f);
    // Non-overlapping 2x2x2 boxes: each parent texel sees exactly its children, so a tileable level
    // yields a tileable level and the mean is preserved exactly (up to float rounding).
    for (int z = 0; z < d; ++z)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          float* out = &dst[((static_cast<size_t>(z) * h + y) * w + x) * ch];
          for (int k = 0; k < sz; ++k)
            for (int j = 0; j < sy; ++j)
              for (int i = 0; i < sx; ++i) {
                const float* in = &src[((static_cast<size_t>(z * sz + k) * ph + (y * sy + j)) * pw + (x * sx + i)) * ch];
                for (int c = 0; c < ch; ++c) out[c] += in[c];
              }
          for (int c = 0; c < ch; ++c) out[c] *= norm;
        }
    tex.mips.push_back(std::move(dst));
  }
}

// ---- The 2023 voxel-cloud noise --------------------------------------------------------------------
// Frequencies (cells per 128-texel tile; the talk samples the tile at position * 0.01, i.e. 100 m):
// low 4 cells (25 m billows), high 8 cells (12.5 m), 3 octaves each, so the high channels reach
// 32 cells = 4 texels per cell at 128^3, still above the texel Nyquist limit.
NoiseTexture generate_voxel_noise(const VoxelNoiseParams& p, Progress* progress) {
  check_size("voxel noise", p.size);
  NoiseTexture tex = make_texture("voxel_noise", p.size, p.size, p.size, 4);
  const uint32_t s_curly_lo = derive_seed(p.seed, 1), s_curly_hi = derive_seed(p.seed, 2);
  const uint32_t s_all_lo = derive_seed(p.seed, 3), s_all_hi = derive_seed(p.seed, 4);
  const int n = p.size;
  const CurlyAlligator curly_lo(p.low_period, p.curly_low, s_curly_lo), curly_hi(p.high_period, p.curly_high, s_curly_hi);
  const AlligatorFbm all_lo(p.low_period, p.octaves, s_all_lo, p.gain), all_hi(p.high_period, p.octaves, s_all_hi, p.gain);
  const float lo = static_cast<float>(p.low_period), hi = static_cast<float>(p.high_period);
  fill_texture(
      tex,
      [&](int x, int y, int z, float* out) {
        glm::vec3 uvw(tc(x, n), tc(y, n), tc(z, n));
        out[0] = curly_lo(uvw * lo);
        out[1] = curly_hi(uvw * hi);
        out[2] = all_lo(uvw * lo);
        out[3] = all_hi(uvw * hi);
      },
      progress);
  normalize_channels(tex);
  build_mips(tex);
  return tex;
}

// ---- The 2015/2017 weather-driven sky set ----------------------------------------------------------

NoiseTexture generate_sky_base(const SkyNoiseParams& p, Progress* progress) {
  check_size("sky base noise", p.base_size);
  NoiseTexture tex = make_texture("sky_noise_base", p.base_size, p.base_size, p.base_size, 4);
  const int n = p.base_size;
  const uint32_t s_pw = derive_seed(p.seed, 10);
  const WorleyFbm pw_worley(p.perlin_worley_period, hash_u32(s_pw ^ 0x7654321u));  // as perlin_worley()
  const WorleyFbm w[3] = {WorleyFbm(p.base_worley_periods[0], derive_seed(p.seed, 11)),
                          WorleyFbm(p.base_worley_periods[1], derive_seed(p.seed, 12)),
                          WorleyFbm(p.base_worley_periods[2], derive_seed(p.seed, 13))};
  const float pwf = static_cast<float>(p.perlin_worley_period);
  fill_texture(
      tex,
      [&](int x, int y, int z, float* out) {
        glm::vec3 uvw(tc(x, n), tc(y, n), tc(z, n));
        out[0] = perlin_worley_combine(perlin_fbm(uvw * pwf, p.perlin_worley_period, p.perlin_octaves, hash_u32(s_pw ^ 0x1234567u)),
                                       pw_worley(uvw * pwf));
        for (int i = 0; i < 3; ++i) out[1 + i] = w[i](uvw * static_cast<float>(p.base_worley_periods[i]));
      },
      progress);
  normalize_channels(tex);
  build_mips(tex);
  return tex;
}

NoiseTexture generate_sky_detail(const SkyNoiseParams& p, Progress* progress) {
  check_size("sky detail noise", p.detail_size);
  NoiseTexture tex = make_texture("sky_noise_detail", p.detail_size, p.detail_size, p.detail_size, 3);
  const int n = p.detail_size;
  const WorleyFbm w[3] = {WorleyFbm(p.detail_worley_periods[0], derive_seed(p.seed, 21)),
                          WorleyFbm(p.detail_worley_periods[1], derive_seed(p.seed, 22)),
                          WorleyFbm(p.detail_worley_periods[2], derive_seed(p.seed, 23))};
  fill_texture(
      tex,
      [&](int x, int y, int z, float* out) {
        glm::vec3 uvw(tc(x, n), tc(y, n), tc(z, n));
        for (int i = 0; i < 3; ++i) out[i] = w[i](uvw * static_cast<float>(p.detail_worley_periods[i]));
      },
      progress);
  normalize_channels(tex);
  build_mips(tex);
  return tex;
}

NoiseTexture generate_curl_2d(const SkyNoiseParams& p, Progress* progress) {
  check_size("curl noise", p.curl_size);
  NoiseTexture tex = make_texture("curl_2d", p.curl_size, p.curl_size, 1, 3);
  const int n = p.curl_size;
  const uint32_t s = derive_seed(p.seed, 30);
  const float cp = static_cast<float>(p.curl_period);
  fill_texture(
      tex,
      [&](int x, int y, int, float* out) {
        // A z = const slice of the 3D field tiles in x and y; the 3 components are the 2015 "3 channels".
        glm::vec3 c = curl(glm::vec3(tc(x, n) * cp, tc(y, n) * cp, 0.5f), p.curl_period, p.curl_octaves, s);
        out[0] = c.x;
        out[1] = c.y;
        out[2] = c.z;
      },
      progress);
  // Signed vectors: one symmetric scale for all channels keeps directions and 0 -> 0.5.
  float m = 1e-6f;
  for (float v : tex.mips[0]) m = std::max(m, std::abs(v));
  for (float& v : tex.mips[0]) v = v / m * 0.5f + 0.5f;
  tex.signed_range = m;
  build_mips(tex);
  return tex;
}

}  // namespace cumulo::clouds
