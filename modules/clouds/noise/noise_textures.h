#pragma once
// The cloud noise textures, generated on the CPU on all cores, as float texels with a full mip chain.
//
//   generate_voxel_noise   2023 voxel-cloud noise (seed 000, "Voxel Cloud Noise", 128^3, 4 channels):
//                          R low / G high frequency Curly-Alligator, B low / A high frequency Alligator.
//   generate_sky_base      2015 (seed 004) first 3D texture, 128^3 RGBA: R Perlin-Worley, G/B/A Worley
//                          fBm at rising frequencies; defines the base shape of the weather-driven sky.
//   generate_sky_detail    2015 second 3D texture, 32^3 RGB: Worley fBm at rising frequencies (erosion).
//   generate_curl_2d       2015 2D texture, 128^2 RGB: curl noise, to distort the detail lookups.
//
// Every channel is remapped linearly so its level-0 minimum is 0 and maximum is 1 (the raw noises have
// narrow, different ranges; full range keeps the 4/8-bit quantisation error relative to the signal
// small). Mips are 2x2x2 box averages of the float level above, so every level tiles and keeps the mean.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "modules/clouds/noise/noise.h"

namespace cumulo {
class Progress;
}

namespace cumulo::clouds {

struct NoiseTexture {
  std::string name;
  int width = 0, height = 0, depth = 0;  // depth 1 for a 2D texture
  int channels = 0;
  // mips[0] is full size; each level is width*height*depth*channels floats in [0, 1], channels
  // interleaved per texel, x fastest, then y, then z.
  std::vector<std::vector<float>> mips;
  // Signed data (curl) is stored as v / (2 * signed_range) + 0.5; 0 for plain 0..1 data.
  float signed_range = 0.0f;

  int level_width(int level) const { return std::max(1, width >> level); }
  int level_height(int level) const { return std::max(1, height >> level); }
  int level_depth(int level) const { return std::max(1, depth >> level); }
  size_t level_texels(int level) const {
    return static_cast<size_t>(level_width(level)) * level_height(level) * level_depth(level);
  }
  int levels() const { return static_cast<int>(mips.size()); }
  float at(int level, int x, int y, int z, int c) const {
    return mips[level][((static_cast<size_t>(z) * level_height(level) + y) * level_width(level) + x) * channels + c];
  }
};

// Frequencies are lattice cells per tile (noise.h periods). Defaults: see the .cpp for the reasoning.
struct VoxelNoiseParams {
  int size = 128;
  uint64_t seed = 1;
  int low_period = 4;   // R and B base frequency (cells per tile)
  int high_period = 8;  // G and A base frequency
  int octaves = 3;
  float gain = 0.5f;
  CurlyAlligatorParams curly_low{3, 0.5f, 2, 2, 0.35f};
  CurlyAlligatorParams curly_high{3, 0.5f, 4, 2, 0.35f};
};

struct SkyNoiseParams {
  int base_size = 128;    // 2015: 128^3
  int detail_size = 32;   // 2015: 32^3
  int curl_size = 128;    // 2015: 128^2
  uint64_t seed = 1;
  int perlin_worley_period = 4;
  int perlin_octaves = 5;
  int base_worley_periods[3] = {4, 8, 16};
  int detail_worley_periods[3] = {2, 4, 8};
  int curl_period = 4;
  int curl_octaves = 3;
};

// `progress` (optional) receives one unit per generated texel of level 0.
NoiseTexture generate_voxel_noise(const VoxelNoiseParams& params, Progress* progress = nullptr);
NoiseTexture generate_sky_base(const SkyNoiseParams& params, Progress* progress = nullptr);
NoiseTexture generate_sky_detail(const SkyNoiseParams& params, Progress* progress = nullptr);
NoiseTexture generate_curl_2d(const SkyNoiseParams& params, Progress* progress = nullptr);

// Building blocks, public for tests and for other generators.
// Fills level 0 of a size_x*size_y*size_z texture by evaluating fn(x, y, z, out[channels]) per texel in
// parallel (rows of texels per task); allocates level 0 from width/height/depth/channels.
using TexelFn = std::function<void(int x, int y, int z, float* out)>;
void fill_texture(NoiseTexture& tex, const TexelFn& fn, Progress* progress);
void normalize_channels(NoiseTexture& tex);  // level 0: per channel, min..max -> 0..1
void build_mips(NoiseTexture& tex);          // box-filtered chain down to 1x1x1 (power-of-two sizes)

}  // namespace cumulo::clouds
