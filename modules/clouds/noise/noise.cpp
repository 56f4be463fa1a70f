#include "modules/clouds/noise/noise.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "engine/core/fbm.h"

namespace cumulo::clouds {

namespace {

// Perlin's improved-noise gradient set: the 12 cube-edge directions, 4 repeated to make 16.
constexpr float kGrad[16][3] = {{1, 1, 0},  {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                {1, 0, -1}, {-1, 0, -1}, {0, 1, 1},  {0, -1, 1},  {0, 1, -1}, {0, -1, -1},
                                {1, 1, 0},  {0, -1, 1}, {-1, 1, 0}, {0, -1, -1}};

inline glm::vec3 corner_gradient(int x, int y, int z, int period, uint32_t seed) {
  const float* g = kGrad[hash_cell(wrap_index(x, period), wrap_index(y, period), wrap_index(z, period), seed) & 15u];
  return {g[0], g[1], g[2]};
}

inline int ifloor(float v) {
  int i = static_cast<int>(v);
  return (static_cast<float>(i) > v) ? i - 1 : i;
}

// Octave i of an fBm: lattice frequency 2^i, period * 2^i, its own seed stream.
inline uint32_t octave_seed(uint32_t seed, int octave) { return hash_u32(seed + 0x9e3779b9u * static_cast<uint32_t>(octave + 1)); }

}  // namespace

uint32_t derive_seed(uint64_t seed, uint32_t stream) {
  uint32_t lo = static_cast<uint32_t>(seed), hi = static_cast<uint32_t>(seed >> 32);
  return hash_u32(hash_u32(lo ^ 0x5bd1e995u) + hash_u32(hi + 0x27d4eb2fu) + stream * 0x85ebca6bu);
}

// ---- Perlin ----------------------------------------------------------------------------------------

glm::vec4 perlin_grad(glm::vec3 p, int period, uint32_t seed) {
  // Value and analytic gradient of the quintic-faded trilinear blend of corner ramps (the closed form
  // popularised by Inigo Quilez); used by curl() so the curl needs no finite differences.
  int ix = ifloor(p.x), iy = ifloor(p.y), iz = ifloor(p.z);
  glm::vec3 f = p - glm::vec3(ix, iy, iz);
  glm::vec3 u = f * f * f * (f * (f * 6.0f - 15.0f) + 10.0f);
  glm::vec3 du = 30.0f * f * f * (f * (f - 2.0f) + 1.0f);

  glm::vec3 ga = corner_gradient(ix, iy, iz, period, seed);
  glm::vec3 gb = corner_gradient(ix + 1, iy, iz, period, seed);
  glm::vec3 gc = corner_gradient(ix, iy + 1, iz, period, seed);
  glm::vec3 gd = corner_gradient(ix + 1, iy + 1, iz, period, seed);
  glm::vec3 ge = corner_gradient(ix, iy, iz + 1, period, seed);
  glm::vec3 gf = corner_gradient(ix + 1, iy, iz + 1, period, seed);
  glm::vec3 gg = corner_gradient(ix, iy + 1, iz + 1, period, seed);
  glm::vec3 gh = corner_gradient(ix + 1, iy + 1, iz + 1, period, seed);

  float va = glm::dot(ga, f);
  float vb = glm::dot(gb, f - glm::vec3(1, 0, 0));
  float vc = glm::dot(gc, f - glm::vec3(0, 1, 0));
  float vd = glm::dot(gd, f - glm::vec3(1, 1, 0));
  float ve = glm::dot(ge, f - glm::vec3(0, 0, 1));
  float vf = glm::dot(gf, f - glm::vec3(1, 0, 1));
  float vg = glm::dot(gg, f - glm::vec3(0, 1, 1));
  float vh = glm::dot(gh, f - glm::vec3(1, 1, 1));

  float k0 = vb - va, k1 = vc - va, k2 = ve - va;
  float k3 = va - vb - vc + vd, k4 = va - vc - ve + vg, k5 = va - vb - ve + vf;
  float k6 = -va + vb + vc - vd + ve - vf - vg + vh;
  float value = va + u.x * k0 + u.y * k1 + u.z * k2 + u.x * u.y * k3 + u.y * u.z * k4 + u.z * u.x * k5 +
                u.x * u.y * u.z * k6;

  glm::vec3 grad = ga + u.x * (gb - ga) + u.y * (gc - ga) + u.z * (ge - ga) + u.x * u.y * (ga - gb - gc + gd) +
                   u.y * u.z * (ga - gc - ge + gg) + u.z * u.x * (ga - gb - ge + gf) +
                   u.x * u.y * u.z * (-ga + gb + gc - gd + ge - gf - gg + gh);
  grad += du * glm::vec3(k0 + u.y * k3 + u.z * k5 + u.y * u.z * k6,  //
                         k1 + u.z * k4 + u.x * k3 + u.z * u.x * k6,  //
                         k2 + u.x * k5 + u.y * k4 + u.x * u.y * k6);
  return {grad, value};
}

float perlin(glm::vec3 p, int period, uint32_t seed) { return perlin_grad(p, period, seed).w; }

glm::vec4 perlin_fbm_grad(glm::vec3 p, int period, int octaves, uint32_t seed, float gain) {
  return fbm(octaves, gain, 2.0f, [&](int o, float freq) {
    glm::vec4 n = perlin_grad(p * freq, period << o, octave_seed(seed, o));
    return glm::vec4(glm::vec3(n) * freq, n.w);  // chain rule: d/dp n(p * freq) = freq * n'
  });
}

float perlin_fbm(glm::vec3 p, int period, int octaves, uint32_t seed, float gain) {
  return fbm(octaves, gain, 2.0f,
             [&](int o, float freq) { return perlin(p * freq, period << o, octave_seed(seed, o)); });
}

// ---- Feature-point lattices (Worley, Alligator) ------------------------------------------------------
// One jittered feature point and one random value per cell, from the cell hash. The hashed and the
// tabulated lattice give bit-identical results (same floats, same loop), so the texture generators can
// use tables while the public point functions need no set-up.

namespace {

inline glm::vec4 hashed_feature(uint32_t h) {
  return {hash_to_unit(h), hash_to_unit(hash_u32(h ^ 0x68e31da4u)), hash_to_unit(hash_u32(h ^ 0xb5297a4du)),
          hash_to_unit(hash_u32(h ^ 0x1b873593u))};
}

struct HashedCells {
  int period;
  uint32_t seed;
  glm::vec4 operator()(int wx, int wy, int wz) const { return hashed_feature(hash_cell(wx, wy, wz, seed)); }
};

struct TableCells {
  const FeatureLattice& lattice;
  glm::vec4 operator()(int wx, int wy, int wz) const { return lattice.cell_wrapped(wx, wy, wz); }
};

// Shared 3x3x3 neighbourhood walk: wrapped indices computed once per axis; cells whose nearest face is
// already farther than `reach` (squared) are skipped before their feature is fetched.
template <typename Cells, typename Visit>
inline void for_each_feature(glm::vec3 p, int period, const Cells& cells, float reach2, Visit&& visit) {
  int ix = ifloor(p.x), iy = ifloor(p.y), iz = ifloor(p.z);
  glm::vec3 f = p - glm::vec3(ix, iy, iz);
  int wx[3], wy[3], wz[3];
  float bx[3], by[3], bz[3];  // squared distance from f to the slab of cell offset -1, 0, +1
  // One modulo per axis; the neighbours wrap by +-1 (the modulo is the costly part of a cell visit).
  auto neighbours = [period](int i, int* w) {
    w[1] = wrap_index(i, period);
    w[0] = w[1] == 0 ? period - 1 : w[1] - 1;
    w[2] = w[1] == period - 1 ? 0 : w[1] + 1;
  };
  neighbours(ix, wx);
  neighbours(iy, wy);
  neighbours(iz, wz);
  bx[0] = f.x * f.x, bx[1] = 0.0f, bx[2] = (1.0f - f.x) * (1.0f - f.x);
  by[0] = f.y * f.y, by[1] = 0.0f, by[2] = (1.0f - f.y) * (1.0f - f.y);
  bz[0] = f.z * f.z, bz[1] = 0.0f, bz[2] = (1.0f - f.z) * (1.0f - f.z);
  for (int dz = 0; dz < 3; ++dz)
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx) {
        if (bx[dx] + by[dy] + bz[dz] >= reach2) continue;
        glm::vec4 c = cells(wx[dx], wy[dy], wz[dz]);
        glm::vec3 d = glm::vec3(dx - 1 + c.x, dy - 1 + c.y, dz - 1 + c.z) - f;
        visit(glm::dot(d, d), c.w);
      }
}

template <typename Cells>
inline float worley_impl(glm::vec3 p, int period, const Cells& cells) {
  // F1 never exceeds sqrt(3) with one point per cell; the cap of 1 makes the pruning radius 1 exact.
  float best = 1.0f;
  for_each_feature(p, period, cells, 1.0f, [&](float d2, float) { best = std::min(best, d2); });
  return std::sqrt(best);
}

// Alligator after SideFX's HDK example: contributions value * s(1 - d) of feature points within d < 1,
// s(t) = t^2 (3 - 2t); result = largest - second largest (0 when none).
template <typename Cells>
inline float alligator_impl(glm::vec3 p, int period, const Cells& cells) {
  float first = 0.0f, second = 0.0f;
  for_each_feature(p, period, cells, 1.0f, [&](float d2, float value) {
    if (d2 >= 1.0f) return;
    float t = 1.0f - std::sqrt(d2);
    float v = value * t * t * (3.0f - 2.0f * t);
    if (v > first) {
      second = first;
      first = v;
    } else if (v > second) {
      second = v;
    }
  });
  return first - second;
}

}  // namespace

FeatureLattice::FeatureLattice(int period, uint32_t seed) : period_(period) {
  cells_.resize(static_cast<size_t>(period) * period * period);
  for (int z = 0; z < period; ++z)
    for (int y = 0; y < period; ++y)
      for (int x = 0; x < period; ++x)
        cells_[(static_cast<size_t>(z) * period + y) * period + x] = hashed_feature(hash_cell(x, y, z, seed));
}

float worley(glm::vec3 p, int period, uint32_t seed) { return worley_impl(p, period, HashedCells{period, seed}); }
float worley(glm::vec3 p, const FeatureLattice& lattice) { return worley_impl(p, lattice.period(), TableCells{lattice}); }

float alligator(glm::vec3 p, int period, uint32_t seed) { return alligator_impl(p, period, HashedCells{period, seed}); }
float alligator(glm::vec3 p, const FeatureLattice& lattice) {
  return alligator_impl(p, lattice.period(), TableCells{lattice});
}

float worley_fbm(glm::vec3 p, int period, uint32_t seed) {
  return 0.625f * (1.0f - worley(p, period, octave_seed(seed, 0))) +
         0.25f * (1.0f - worley(p * 2.0f, period * 2, octave_seed(seed, 1))) +
         0.125f * (1.0f - worley(p * 4.0f, period * 4, octave_seed(seed, 2)));
}

WorleyFbm::WorleyFbm(int period, uint32_t seed) {
  for (int o = 0; o < 3; ++o) octaves_.emplace_back(period << o, octave_seed(seed, o));
}
float WorleyFbm::operator()(glm::vec3 p) const {
  return 0.625f * (1.0f - worley(p, octaves_[0])) + 0.25f * (1.0f - worley(p * 2.0f, octaves_[1])) +
         0.125f * (1.0f - worley(p * 4.0f, octaves_[2]));
}

float perlin_worley(glm::vec3 p, int period, int perlin_octaves, uint32_t seed) {
  float w = worley_fbm(p, period, hash_u32(seed ^ 0x7654321u));
  return perlin_worley_combine(perlin_fbm(p, period, perlin_octaves, hash_u32(seed ^ 0x1234567u)), w);
}

float perlin_worley_combine(float perlin_fbm_value, float worley_fbm_value) {
  // The normalised fBm is narrow (std ~0.16 for 4-5 octaves); stretch +-2 std to 0..1 first, as the
  // 2017 formula expects a full-range Perlin texture (a 0.5 +- 0.5 mapping would leave Perlin mostly
  // below 1 - worley and the channel mostly 0).
  float perlin01 = std::clamp(perlin_fbm_value * 1.5f + 0.5f, 0.0f, 1.0f);
  // remap(v, lo, hi, 0, 1) with lo = 1 - worley, hi = 1; guard the (practically unreachable) worley = 0.
  float lo = 1.0f - worley_fbm_value;
  return std::clamp((perlin01 - lo) / std::max(1e-4f, 1.0f - lo), 0.0f, 1.0f);
}

float alligator_fbm(glm::vec3 p, int period, int octaves, uint32_t seed, float gain) {
  return fbm(octaves, gain, 2.0f,
             [&](int o, float freq) { return alligator(p * freq, period << o, octave_seed(seed, o)); });
}

AlligatorFbm::AlligatorFbm(int period, int octaves, uint32_t seed, float gain) : gain_(gain) {
  for (int o = 0; o < octaves; ++o) octaves_.emplace_back(period << o, octave_seed(seed, o));
}
float AlligatorFbm::operator()(glm::vec3 p) const {
  return fbm(int(octaves_.size()), gain_, 2.0f, [&](int o, float freq) { return alligator(p * freq, octaves_[o]); });
}

// ---- Curl -----------------------------------------------------------------------------------------

glm::vec3 curl(glm::vec3 p, int period, int octaves, uint32_t seed) {
  // Potential octaves fall off by 1/4 so that their derivatives (x2 per octave) fall off by 1/2: with
  // the usual 1/2 every octave would contribute equally to the curl and it would look like grain.
  constexpr float kGain = 0.25f;
  glm::vec3 gx(perlin_fbm_grad(p, period, octaves, hash_u32(seed + 1u), kGain));
  glm::vec3 gy(perlin_fbm_grad(p, period, octaves, hash_u32(seed + 2u), kGain));
  glm::vec3 gz(perlin_fbm_grad(p, period, octaves, hash_u32(seed + 3u), kGain));
  // curl(psi) = (dpsi_z/dy - dpsi_y/dz, dpsi_x/dz - dpsi_z/dx, dpsi_y/dx - dpsi_x/dy)
  return {gz.y - gy.z, gx.z - gz.x, gy.x - gx.y};
}

// ---- Curly-Alligator ------------------------------------------------------------------------------

glm::vec3 curly_alligator_warp(glm::vec3 p, int period, const CurlyAlligatorParams& params, uint32_t seed) {
  float to_curl = static_cast<float>(params.curl_period) / static_cast<float>(period);
  return params.curl_strength * curl(p * to_curl, params.curl_period, params.curl_octaves, hash_u32(seed ^ 0xc2b2ae35u));
}

float curly_alligator(glm::vec3 p, int period, const CurlyAlligatorParams& params, uint32_t seed) {
  glm::vec3 warp = curly_alligator_warp(p, period, params, seed);
  return 1.0f - alligator_fbm(p + warp, period, params.octaves, seed, params.gain);
}

CurlyAlligator::CurlyAlligator(int period, const CurlyAlligatorParams& params, uint32_t seed)
    : period_(period), params_(params), seed_(seed), alligator_(period, params.octaves, seed, params.gain) {}
float CurlyAlligator::operator()(glm::vec3 p) const {
  return 1.0f - alligator_(p + curly_alligator_warp(p, period_, params_, seed_));
}

}  // namespace cumulo::clouds
