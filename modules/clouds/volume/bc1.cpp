#include "modules/clouds/volume/bc1.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "engine/core/parallel.h"
#include "engine/core/progress.h"

namespace cumulo::clouds {

namespace {

constexpr int e5(int k) { return (k << 3) | (k >> 2); }
constexpr int e6(int k) { return (k << 2) | (k >> 4); }
uint16_t pack565(int r, int g, int b) { return static_cast<uint16_t>((r << 11) | (g << 5) | b); }

// Interpolated entry 2/3 a + 1/3 b of 8-bit values under a model, as 0..255 (possibly fractional).
double interp(int a, int b, Bc1Model m) {
  switch (m) {
    case Bc1Model::Exact: return (2.0 * a + b) / 3.0;
    case Bc1Model::Round: return static_cast<double>((2 * a + b + 1) / 3);
    case Bc1Model::Floor: return static_cast<double>((2 * a + b) / 3);
    case Bc1Model::Amd: return static_cast<double>((43 * a + 21 * b + 32) >> 6);
  }
  return 0.0;
}

// A float32 dot product in the shader may round up by an ulp or so: keep decodes this far below
// the value (2^-21 of the 0..1 range = 2 mm).
constexpr double kDotMargin = 1.0 / 2097152.0;

uint32_t index_bits(const uint8_t* block) {
  return uint32_t(block[4]) | (uint32_t(block[5]) << 8) | (uint32_t(block[6]) << 16) | (uint32_t(block[7]) << 24);
}

void write_block(uint8_t* out, uint16_t c0, uint16_t c1, uint32_t bits) {
  out[0] = c0 & 0xFF, out[1] = c0 >> 8, out[2] = c1 & 0xFF, out[3] = c1 >> 8;
  out[4] = bits & 0xFF, out[5] = (bits >> 8) & 0xFF, out[6] = (bits >> 16) & 0xFF, out[7] = bits >> 24;
}

// Exact and upper-bound (over every model) scalar decode of the 4-colour palette c0 > c1.
void sdf_palette(uint16_t c0, uint16_t c1, double exact[4], double upper[4]) {
  glm::ivec3 a = bc1_expand(c0), b = bc1_expand(c1);
  exact[0] = upper[0] = sdf_unpack(glm::dvec3(a) / 255.0);
  exact[1] = upper[1] = sdf_unpack(glm::dvec3(b) / 255.0);
  for (int e = 0; e < 2; ++e) {
    glm::ivec3 p = e == 0 ? a : b, q = e == 0 ? b : a;  // entry 2 leans to c0, entry 3 to c1
    glm::dvec3 ex, up(0.0);
    for (int c = 0; c < 3; ++c) {
      ex[c] = interp(p[c], q[c], Bc1Model::Exact);
      for (Bc1Model m : kBc1Models) up[c] = std::max(up[c], interp(p[c], q[c], m));
    }
    exact[2 + e] = sdf_unpack(ex / 255.0);
    upper[2 + e] = sdf_unpack(up / 255.0);
  }
}

// One 4x4 block of targets (0..1, already lowered by the margin). Tries every texel's round-down as
// the high endpoint (the talk: "adjust the high endpoint value down to improve average error") and
// keeps the one with the least total error; each texel takes the highest entry that stays below it.
void encode_sdf_block(const double t[16], uint8_t out[8]) {
  double tmin = t[0], tmax = t[0];
  for (int i = 1; i < 16; ++i) tmin = std::min(tmin, t[i]), tmax = std::max(tmax, t[i]);
  const uint16_t lo = sdf_endpoint_round_down(tmin);
  if (tmin == tmax) {
    write_block(out, lo, lo, 0);  // c0 == c1: every texel reads c0
    return;
  }
  double best_err = std::numeric_limits<double>::infinity();
  uint16_t best_c0 = lo, best_c1 = lo;
  uint32_t best_bits = 0;
  // Candidates for the high endpoint: each texel's own round-down, and the endpoints that put an
  // interpolated entry (1/3 or 2/3 of the way from the low endpoint) right at a texel's value.
  const double slo = sdf_unpack(glm::dvec3(bc1_expand(lo)) / 255.0);
  double cand[48];
  int ncand = 0;
  for (int k = 0; k < 16; ++k) {
    cand[ncand++] = t[k];
    if (t[k] > slo) {
      cand[ncand++] = std::min(1.0, slo + 3.0 * (t[k] - slo));
      cand[ncand++] = std::min(1.0, slo + 1.5 * (t[k] - slo));
    }
  }
  uint16_t tried[48];
  int ntried = 0;
  for (int k = 0; k < ncand; ++k) {
    uint16_t hi = sdf_endpoint_round_down(cand[k]);
    if (std::find(tried, tried + ntried, hi) != tried + ntried) continue;
    tried[ntried++] = hi;
    if (hi == lo) {
      double err = 0.0;
      double s = sdf_unpack(glm::dvec3(bc1_expand(lo)) / 255.0);
      for (int i = 0; i < 16; ++i) err += t[i] - s;
      if (err < best_err) best_err = err, best_c0 = lo, best_c1 = lo, best_bits = 0;
      continue;
    }
    uint16_t c0 = std::max(hi, lo), c1 = std::min(hi, lo);  // 4-colour mode needs c0 > c1
    double ex[4], up[4];
    sdf_palette(c0, c1, ex, up);
    double err = 0.0;
    uint32_t bits = 0;
    for (int i = 0; i < 16; ++i) {
      int pick = -1;
      for (int j = 0; j < 4; ++j)
        if (up[j] <= t[i] && (pick < 0 || ex[j] > ex[pick])) pick = j;
      // The low endpoint (whichever of c0, c1 it is) is always <= every target.
      err += t[i] - ex[pick];
      bits |= uint32_t(pick) << (2 * i);
    }
    if (err < best_err) best_err = err, best_c0 = c0, best_c1 = c1, best_bits = bits;
  }
  write_block(out, best_c0, best_c1, best_bits);
}

template <typename Fn>
void for_each_block(glm::uvec3 dims, Progress* progress, Fn&& fn) {
  const uint32_t bx = (dims.x + 3) / 4, by = (dims.y + 3) / 4;
  const size_t total = size_t(bx) * by * dims.z;
  // Chunks of 1024 blocks so the progress line moves and threads share the work evenly.
  parallel_for((total + 1023) / 1024, [&](size_t cb, size_t ce) {
    for (size_t chunk = cb; chunk < ce; ++chunk) {
      size_t end = std::min(total, (chunk + 1) * 1024);
      for (size_t blk = chunk * 1024; blk < end; ++blk) {
        uint32_t x = static_cast<uint32_t>(blk % bx), rest = static_cast<uint32_t>(blk / bx);
        uint32_t y = rest % by, z = rest / by;
        fn(blk, x * 4, y * 4, z);
      }
      if (progress) progress->add(double(end - chunk * 1024));
    }
  });
}

}  // namespace

glm::ivec3 bc1_expand(uint16_t c) { return {e5((c >> 11) & 31), e6((c >> 5) & 63), e5(c & 31)}; }

void bc1_palette(uint16_t c0, uint16_t c1, Bc1Model model, glm::dvec3 out[4]) {
  glm::ivec3 a = bc1_expand(c0), b = bc1_expand(c1);
  out[0] = glm::dvec3(a) / 255.0;
  out[1] = glm::dvec3(b) / 255.0;
  if (c0 > c1) {
    for (int c = 0; c < 3; ++c) {
      out[2][c] = interp(a[c], b[c], model) / 255.0;
      out[3][c] = interp(b[c], a[c], model) / 255.0;
    }
  } else {
    // Three-colour mode: the midpoint (models differ by at most rounding; take the spec's) and black.
    out[2] = (glm::dvec3(a) + glm::dvec3(b)) / 510.0;
    if (model != Bc1Model::Exact) out[2] = glm::floor((glm::dvec3(a) + glm::dvec3(b) + (model == Bc1Model::Floor ? 0.0 : 1.0)) / 2.0) / 255.0;
    out[3] = glm::dvec3(0.0);
  }
}

glm::dvec3 bc1_decode_texel_model(const uint8_t* block, uint32_t tx, uint32_t ty, Bc1Model model) {
  uint16_t c0 = uint16_t(block[0] | (block[1] << 8)), c1 = uint16_t(block[2] | (block[3] << 8));
  glm::dvec3 pal[4];
  bc1_palette(c0, c1, model, pal);
  return pal[(index_bits(block) >> (2 * (ty * 4 + tx))) & 3u];
}

glm::vec4 bc1_decode_texel(const uint8_t* block, uint32_t tx, uint32_t ty) {
  const bool three_colour = (block[0] | (block[1] << 8)) <= (block[2] | (block[3] << 8));
  const bool transparent = three_colour && ((index_bits(block) >> (2 * (ty * 4 + tx))) & 3u) == 3u;
  return glm::vec4(glm::vec3(bc1_decode_texel_model(block, tx, ty, Bc1Model::Exact)), transparent ? 0.0f : 1.0f);
}

uint16_t sdf_endpoint_round_down(double v) {
  // gConvertScalarToDXT1Endpoint_RoundDown from the talk, with the exact bit-replicated levels.
  int r = 0;
  for (int k = 31; k >= 0; --k)
    if (e5(k) / 255.0 <= v) {
      r = k;
      break;
    }
  double rest = v - e5(r) / 255.0;
  int g = 0;
  for (int k = 63; k >= 0; --k)
    if (e6(k) / 255.0 * kSdfDotG <= rest) {
      g = k;
      break;
    }
  rest -= e6(g) / 255.0 * kSdfDotG;
  int b = 0;
  for (int k = 31; k >= 0; --k)
    if (e5(k) / 255.0 * kSdfDotB <= rest) {
      b = k;
      break;
    }
  return pack565(r, g, b);
}

std::vector<uint8_t> encode_sdf_bc1(const std::vector<uint16_t>& values, glm::uvec3 dims, Progress* progress) {
  const uint32_t bx = (dims.x + 3) / 4, by = (dims.y + 3) / 4;
  std::vector<uint8_t> out(size_t(bx) * by * dims.z * 8);
  for_each_block(dims, progress, [&](size_t blk, uint32_t x0, uint32_t y0, uint32_t z) {
    double t[16];
    for (uint32_t j = 0; j < 4; ++j)
      for (uint32_t i = 0; i < 4; ++i) {
        // Partial blocks repeat the edge texel (those texels are never sampled).
        uint32_t x = std::min(x0 + i, dims.x - 1), y = std::min(y0 + j, dims.y - 1);
        double v = values[x + size_t(dims.x) * (y + size_t(dims.y) * z)] / 65535.0;
        t[j * 4 + i] = std::max(0.0, v - kDotMargin);
      }
    encode_sdf_block(t, &out[blk * 8]);
  });
  return out;
}

Bc1SdfReport verify_sdf_bc1(const std::vector<uint8_t>& blocks, const std::vector<uint16_t>& values, glm::uvec3 dims,
                            const std::vector<float>* reference) {
  const size_t n = size_t(dims.x) * dims.y * dims.z;
  const uint32_t bx = (dims.x + 3) / 4, by = (dims.y + 3) / 4;
  std::vector<double> upper(n), exact(n);
  const double range = 4096.0 + 256.0;
  parallel_for(size_t(dims.y) * dims.z, [&](size_t b, size_t e) {
    for (size_t row = b; row < e; ++row) {
      uint32_t y = row % dims.y, z = row / dims.y;
      for (uint32_t x = 0; x < dims.x; ++x) {
        const uint8_t* blk = &blocks[((size_t(z) * by + y / 4) * bx + x / 4) * 8];
        double up = 0.0;
        for (Bc1Model m : kBc1Models) up = std::max(up, sdf_unpack(bc1_decode_texel_model(blk, x % 4, y % 4, m)));
        size_t i = x + size_t(dims.x) * row;
        upper[i] = up;
        exact[i] = sdf_unpack(bc1_decode_texel_model(blk, x % 4, y % 4, Bc1Model::Exact));
      }
    }
  });
  Bc1SdfReport r;
  r.texels = n;
  double sum = 0.0, sum_f = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double v = values[i] / 65535.0;
    if (upper[i] > v) ++r.violations;
    double err = (v - exact[i]) * range;
    sum += err;
    r.max_error_m = std::max(r.max_error_m, err);
    if (reference) {
      double ef = ((*reference)[i] + 256.0) - exact[i] * range;
      sum_f += ef;
      r.max_error_vs_float_m = std::max(r.max_error_vs_float_m, ef);
    }
  }
  r.mean_error_m = n ? sum / n : 0.0;
  r.mean_error_vs_float_m = n && reference ? sum_f / n : 0.0;

  // Bilinear/trilinear filtering is a convex combination: check the half-way points between
  // neighbours along each axis and the centre of every 2x2x2 cell.
  auto at = [&](uint32_t x, uint32_t y, uint32_t z) { return x + size_t(dims.x) * (y + size_t(dims.y) * z); };
  for (uint32_t z = 0; z < dims.z; ++z)
    for (uint32_t y = 0; y < dims.y; ++y)
      for (uint32_t x = 0; x < dims.x; ++x) {
        size_t i = at(x, y, z);
        const uint32_t nb[3][3] = {{x + 1, y, z}, {x, y + 1, z}, {x, y, z + 1}};
        for (int a = 0; a < 3; ++a) {
          if (nb[a][0] >= dims.x || nb[a][1] >= dims.y || nb[a][2] >= dims.z) continue;
          size_t j = at(nb[a][0], nb[a][1], nb[a][2]);
          ++r.midpoint_checks;
          if (0.5 * (upper[i] + upper[j]) > 0.5 * (values[i] + values[j]) / 65535.0) ++r.midpoint_violations;
        }
        if (x + 1 < dims.x && y + 1 < dims.y && z + 1 < dims.z) {
          double su = 0.0, sv = 0.0;
          for (int k = 0; k < 8; ++k) {
            size_t j = at(x + (k & 1), y + ((k >> 1) & 1), z + (k >> 2));
            su += upper[j], sv += values[j] / 65535.0;
          }
          ++r.midpoint_checks;
          if (su * 0.125 > sv * 0.125) ++r.midpoint_violations;
        }
      }
  return r;
}

std::vector<uint8_t> encode_rgb_bc1(const std::vector<float>& rgb, glm::uvec3 dims, glm::vec3 weights,
                                    Progress* progress) {
  const uint32_t bx = (dims.x + 3) / 4, by = (dims.y + 3) / 4;
  std::vector<uint8_t> out(size_t(bx) * by * dims.z * 8);
  const glm::dvec3 w(weights);
  for_each_block(dims, progress, [&](size_t blk, uint32_t x0, uint32_t y0, uint32_t z) {
    glm::dvec3 px[16];
    glm::dvec3 mn(1e9), mx(-1e9);
    for (uint32_t j = 0; j < 4; ++j)
      for (uint32_t i = 0; i < 4; ++i) {
        uint32_t x = std::min(x0 + i, dims.x - 1), y = std::min(y0 + j, dims.y - 1);
        const float* c = &rgb[3 * (x + size_t(dims.x) * (y + size_t(dims.y) * z))];
        px[j * 4 + i] = glm::dvec3(c[0], c[1], c[2]);
        mn = glm::min(mn, px[j * 4 + i]), mx = glm::max(mx, px[j * 4 + i]);
      }
    auto quant = [](glm::dvec3 c) {
      return pack565(static_cast<int>(std::lround(std::clamp(c.x, 0.0, 1.0) * 31)),
                     static_cast<int>(std::lround(std::clamp(c.y, 0.0, 1.0) * 63)),
                     static_cast<int>(std::lround(std::clamp(c.z, 0.0, 1.0) * 31)));
    };
    double best = std::numeric_limits<double>::infinity();
    uint16_t bc0 = 0, bc1c = 0;
    uint32_t bbits = 0;
    // The four diagonals of the block's colour box (channels may rise or fall together).
    for (int diag = 0; diag < 4; ++diag) {
      glm::dvec3 a = mn, b = mx;
      if (diag & 1) std::swap(a.y, b.y);
      if (diag & 2) std::swap(a.z, b.z);
      uint16_t c0 = quant(b), c1 = quant(a);
      if (c0 < c1) std::swap(c0, c1);
      glm::dvec3 pal[4];
      bc1_palette(c0, c1, Bc1Model::Exact, pal);
      int entries = c0 > c1 ? 4 : 1;
      double err = 0.0;
      uint32_t bits = 0;
      for (int i = 0; i < 16; ++i) {
        int pick = 0;
        double pe = std::numeric_limits<double>::infinity();
        for (int k = 0; k < entries; ++k) {
          glm::dvec3 d = (pal[k] - px[i]) * w;
          double e2 = glm::dot(d, d);
          if (e2 < pe) pe = e2, pick = k;
        }
        err += pe;
        bits |= uint32_t(pick) << (2 * i);
      }
      if (err < best) best = err, bc0 = c0, bc1c = c1, bbits = bits;
    }
    write_block(&out[blk * 8], bc0, bc1c, bbits);
  });
  return out;
}

Bc1RgbReport measure_rgb_bc1(const std::vector<uint8_t>& blocks, const std::vector<float>& rgb, glm::uvec3 dims) {
  const uint32_t bx = (dims.x + 3) / 4, by = (dims.y + 3) / 4;
  Bc1RgbReport r;
  glm::dvec3 sum(0.0);
  const size_t n = size_t(dims.x) * dims.y * dims.z;
  for (uint32_t z = 0; z < dims.z; ++z)
    for (uint32_t y = 0; y < dims.y; ++y)
      for (uint32_t x = 0; x < dims.x; ++x) {
        const uint8_t* blk = &blocks[((size_t(z) * by + y / 4) * bx + x / 4) * 8];
        glm::dvec3 d = bc1_decode_texel_model(blk, x % 4, y % 4, Bc1Model::Exact);
        const float* c = &rgb[3 * (x + size_t(dims.x) * (y + size_t(dims.y) * z))];
        glm::dvec3 e = glm::abs(d - glm::dvec3(c[0], c[1], c[2]));
        sum += e * e;
        r.max_error = glm::max(r.max_error, e);
      }
  r.rmse = n ? glm::sqrt(sum / double(n)) : glm::dvec3(0.0);
  return r;
}

}  // namespace cumulo::clouds
