#pragma once
// splitmix64 (Vigna): a small, well-mixed stream in fixed integer arithmetic, so every platform draws
// the same sequence for a seed (terrain generation, recipe particles, the weather scheduler, lightning).
//
//   SplitMix64 rng{seed};
//   float u = rng.uniform();         // [0, 1), 24 bits
//   float x = rng.range(10.0f, 30.0f);
#include <cstdint>

namespace cumulo {

struct SplitMix64 {
  uint64_t state = 0;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); }
  float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
};

}  // namespace cumulo
