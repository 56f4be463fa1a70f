#pragma once
// Tileable procedural noises for clouds: the building blocks of the 2015/2017 sky noise set
// (Perlin, Worley, Perlin-Worley, curl) and of the 2023 voxel-cloud noise (Alligator, Curly-Alligator).
//
// Index
//   hash_cell / hash_to_unit   integer lattice hashing (seeded, platform independent)
//   perlin, perlin_grad         improved gradient noise, value in ~[-1,1], analytic gradient
//   perlin_fbm, perlin_fbm_grad octaves at doubling frequency, normalised by the amplitude sum
//   worley, worley_fbm          F1 cellular distance (one jittered point per cell); 2015 inverted fBm
//   perlin_worley               2017 seed 001: remap(perlin, 1 - worley, 1, 0, 1)
//   alligator, alligator_fbm    Houdini's Alligator noise (see alligator())
//   curl                        curl of a tileable vector potential: divergence-free, for distortion
//   curly_alligator             2023: inverted Alligator looked up at a curl-distorted position
//   FeatureLattice, WorleyFbm,  tabulated per-cell feature points: the same values as the hashed
//   AlligatorFbm, CurlyAlligator  functions, several times faster for millions of points (bakes)
//
// Erosion example (a baker eroding a shape with billows, 25 m cells tiling every 100 m):
//   static const AlligatorFbm billows(4, 3, derive_seed(seed, 7));
//   float n = billows(world_pos / 100.0f * 4.0f);   // ~[0, 0.7], mean ~0.17: bright cells, dark webs
//
// Tiling: every function takes `period`, in lattice cells; every lattice (cell) lookup wraps by it,
// so f(p + period * k) == f(p) for any integer vector k. To fill an N^3 tileable texture with F
// cells across it, evaluate at p = (texel + 0.5) / N * F with period F. Octave i of an fBm uses the
// lattice at frequency 2^i with period * 2^i, so fBms tile with the base period too.
//
// Determinism: integer hashing and float arithmetic in a fixed order; the same seed gives the same
// values on every run and thread count.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace cumulo::clouds {

// ---- Hashing --------------------------------------------------------------------------------------
// "lowbias32" integer finaliser (Chris Wellons' hash-prospector): cheap, well mixed, no tables.
inline uint32_t hash_u32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
inline uint32_t hash_cell(int x, int y, int z, uint32_t seed) {
  return hash_u32(static_cast<uint32_t>(x) + hash_u32(static_cast<uint32_t>(y) + hash_u32(static_cast<uint32_t>(z) + seed)));
}
// Top 24 bits as a float in [0, 1).
inline float hash_to_unit(uint32_t h) { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }
// Euclidean modulo: the lattice index that tiles with `period` (period > 0).
inline int wrap_index(int i, int period) {
  int m = i % period;
  return m < 0 ? m + period : m;
}
// Mixes a user seed and a stream id into the 32-bit seed the noises take.
uint32_t derive_seed(uint64_t seed, uint32_t stream);

// ---- Perlin ----------------------------------------------------------------------------------------
// Improved Perlin noise (2002: quintic fade, 12 edge gradients). Value roughly in [-1, 1].
float perlin(glm::vec3 p, int period, uint32_t seed = 0);
// xyz = gradient d(value)/dp, w = value (same value as perlin()).
glm::vec4 perlin_grad(glm::vec3 p, int period, uint32_t seed = 0);
// Sum over octaves of gain^i * perlin(p * 2^i, period * 2^i), divided by the amplitude sum.
float perlin_fbm(glm::vec3 p, int period, int octaves, uint32_t seed = 0, float gain = 0.5f);
glm::vec4 perlin_fbm_grad(glm::vec3 p, int period, int octaves, uint32_t seed = 0, float gain = 0.5f);

// ---- Worley ----------------------------------------------------------------------------------------
// F1: distance from p to the nearest feature point, one uniformly jittered point per cell, clamped
// to [0, 1] (in cell units).
float worley(glm::vec3 p, int period, uint32_t seed = 0);
// 2015 (seed 004, "layered like the standard Perlin fBm approach"): inverted Worley (1 - F1) at
// frequencies 1x, 2x, 4x, weighted 0.625, 0.25, 0.125 (the weights of Hillaire's TileableVolumeNoise,
// which the 2017 talk points to). Value in [0, 1], 1 at feature points (billow centres).
float worley_fbm(glm::vec3 p, int period, uint32_t seed = 0);
// 2017 (seed 001): perlin-worley = remap(perlin, 1 - worley, 1, 0, 1), with perlin the fBm stretched to 0..1 and
// worley the inverted Worley fBm at the same base frequency; "subtract the web-like shapes of Worley
// noise from the low density regions of Perlin noise". Saturated to [0, 1].
float perlin_worley(glm::vec3 p, int period, int perlin_octaves, uint32_t seed = 0);

// ---- Feature-point lattices ----------------------------------------------------------------------
// The per-cell feature points (xyz jitter in [0,1), w = random value) of one (period, seed), tabulated
// once. The lattice overloads below return exactly what the hashed versions return, faster: use them
// when evaluating millions of points (texture generation, baking).
class FeatureLattice {
 public:
  FeatureLattice(int period, uint32_t seed);
  int period() const { return period_; }
  glm::vec4 cell_wrapped(int x, int y, int z) const {  // x, y, z already in [0, period)
    return cells_[(static_cast<size_t>(z) * period_ + y) * period_ + x];
  }

 private:
  int period_;
  std::vector<glm::vec4> cells_;
};
float worley(glm::vec3 p, const FeatureLattice& lattice);
float alligator(glm::vec3 p, const FeatureLattice& lattice);

// Tabulated equivalents of worley_fbm(p, period, seed) and alligator_fbm(p, period, octaves, seed, gain).
class WorleyFbm {
 public:
  WorleyFbm(int period, uint32_t seed);
  float operator()(glm::vec3 p) const;

 private:
  std::vector<FeatureLattice> octaves_;
};
class AlligatorFbm {
 public:
  AlligatorFbm(int period, int octaves, uint32_t seed, float gain = 0.5f);
  float operator()(glm::vec3 p) const;

 private:
  float gain_;
  std::vector<FeatureLattice> octaves_;
};
// The Perlin-Worley combination of a perlin_fbm value (~[-1,1]) and a worley_fbm value ([0,1]).
float perlin_worley_combine(float perlin_fbm_value, float worley_fbm_value);

// ---- Alligator ------------------------------------------------------------------------------------
// Alligator noise, after SideFX's HDK example (alligator.C, cited by the 2023 talk): every cell of the
// 3x3x3 neighbourhood holds one jittered feature point with a random value v; a point within distance
// d < 1 contributes v * s(1 - d), s(t) = t^2 (3 - 2t) (a smooth radial falloff); the result is the
// largest contribution minus the second largest. Value in [0, 1); ridges where two cells tie.
float alligator(glm::vec3 p, int period, uint32_t seed = 0);
// Houdini-style turbulence: octaves at doubling frequency, amplitude * gain per octave, normalised
// by the amplitude sum. Each octave uses its own seed stream.
float alligator_fbm(glm::vec3 p, int period, int octaves, uint32_t seed = 0, float gain = 0.5f);

// ---- Curl -----------------------------------------------------------------------------------------
// curl(psi) of the vector potential psi = three independent perlin_fbm fields (gain 1/4, so the
// derivative octaves fall off by 1/2):
// divergence-free, as the 2015 talk uses it "to fake fluid motion". Components are in potential units
// per cell (typically |curl| ~ 0.5..2).
glm::vec3 curl(glm::vec3 p, int period, int octaves = 2, uint32_t seed = 0);

// ---- Curly-Alligator ------------------------------------------------------------------------------
// 2023 talk: "we started with inverted alligator noise, which creates nice web like shapes, and then
// distorted it using curl noise." p and `period` are in Alligator cells; the curl field is looked up
// at p * curl_period / period with its own (integer) period, so the distortion tiles with the same tile.
struct CurlyAlligatorParams {
  int octaves = 3;           // Alligator octaves
  float gain = 0.5f;         // Alligator octave gain
  int curl_period = 4;       // curl lattice cells per tile (lower = larger swirls)
  int curl_octaves = 2;
  float curl_strength = 0.35f;  // displacement in Alligator cells per unit of curl (at the base octave)
};
float curly_alligator(glm::vec3 p, int period, const CurlyAlligatorParams& params, uint32_t seed = 0);
// The displacement (in Alligator cells) that curly_alligator applies at p.
glm::vec3 curly_alligator_warp(glm::vec3 p, int period, const CurlyAlligatorParams& params, uint32_t seed = 0);
// Tabulated equivalent of curly_alligator(p, period, params, seed).
class CurlyAlligator {
 public:
  CurlyAlligator(int period, const CurlyAlligatorParams& params, uint32_t seed);
  float operator()(glm::vec3 p) const;

 private:
  int period_;
  CurlyAlligatorParams params_;
  uint32_t seed_;
  AlligatorFbm alligator_;
};

}  // namespace cumulo::clouds
