#pragma once
// Fractional Brownian motion: the one octave loop behind every fBm in the engine and its modules (the
// cloud noises, the baker's erosion, the terrain generator). The noise itself is the caller's:
//
//   float n = cumulo::fbm(octaves, 0.5f, 2.0f, [&](int o, float freq) { return perlin(p * freq, seed + o); });
//
// Octave o is weighted gain^o and sampled at lacunarity^o; the sum is divided by the sum of the weights,
// so an fBm of a noise in [-1, 1] stays in [-1, 1]. T is float or a glm vector (e.g. value + gradient).
// The float operations and their order are part of the baked outputs' bytes: change them and the noise
// textures, bakes and terrain change.

namespace cumulo {

template <typename Octave>
auto fbm(int octaves, float gain, float lacunarity, Octave&& octave) {
  using T = decltype(octave(0, 1.0f));
  T sum(0.0f);
  float amp = 1.0f, freq = 1.0f, total = 0.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * octave(o, freq);
    total += amp;
    amp *= gain;
    freq *= lacunarity;
  }
  return sum / total;
}

}  // namespace cumulo
