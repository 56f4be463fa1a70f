#pragma once
// Storage of the noise textures: quantisation to the GPU formats, conversion to clouds::Volume (the
// .nvdf file), and the quality measurements behind the format choice.
//
// The 2023 talk stores the 4-channel voxel noise "Uncompressed, 2 Bytes / Texel, 4.194 Megabytes"
// (128^3 x 2 B = 4,194,304 B): 4 bits per channel, i.e. VK_FORMAT_R4G4B4A4_UNORM_PACK16. We produce
// that and RGBA8 (8,388,608 B at level 0) and measure both (`cumulo noise` prints the figures; the
// measured numbers and the choice, RGBA8 by default, are in noise_command.cpp's header comment).
// On Vulkan, R4G4B4A4_UNORM_PACK16 sampling is optional (lavapipe lacks it): upload the same bytes as
// B4G4R4A4_UNORM_PACK16 (mandatory) with a view swizzle r <- b, b <- r (see tests/.../noise_gpu_util.h).
//
// Each mip level is quantised from the float level (not from the quantised parent), round to nearest,
// so a level's error is at most half a step: 1/30 for 4 bits, 1/510 for 8 bits.
#include <cstdint>
#include <string>
#include <vector>

#include "modules/clouds/noise/noise_textures.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

// VK_FORMAT_R4G4B4A4_UNORM_PACK16 bit order: R in bits 12-15, G 8-11, B 4-7, A 0-3 (as VolumeEncoding).
uint16_t pack_r4g4b4a4(float r, float g, float b, float a);
float unpack_r4g4b4a4(uint16_t word, int channel);  // channel 0 = R .. 3 = A, value in 0..1

// Converts a NoiseTexture (all mips) into a Volume of `encoding` (RGBA8, R4G4B4A4, RGBA16 or R32F-
// compatible single channel). `tile_metres` sets voxel size and bounds: the talk samples the voxel noise
// at position * 0.01, i.e. one tile per 100 m. Channel names come from `channel_names` (semantic
// "noise"); `decode_min/max` per channel default to 0..1.
struct NoiseChannelInfo {
  std::string name;
  float decode_min = 0.0f, decode_max = 1.0f;
};
Volume noise_to_volume(const NoiseTexture& tex, VolumeEncoding encoding, const std::vector<NoiseChannelInfo>& channels,
                       float tile_metres = 100.0f);

// The channels of the noise files (`cumulo noise`, the renderer's caches), in the order the shaders read.
inline const std::vector<NoiseChannelInfo> kVoxelChannels = {
    {"curly_alligator_low"}, {"curly_alligator_high"}, {"alligator_low"}, {"alligator_high"}};
inline const std::vector<NoiseChannelInfo> kSkyBaseChannels = {
    {"perlin_worley"}, {"worley_low"}, {"worley_mid"}, {"worley_high"}};
inline const std::vector<NoiseChannelInfo> kSkyDetailChannels = {{"worley_low"}, {"worley_mid"}, {"worley_high"}};
// The 2D curl texture's channels: signed, decoded over +-signed_range.
inline std::vector<NoiseChannelInfo> curl_channels(float signed_range) {
  return {{"curl_x", -signed_range, signed_range}, {"curl_y", -signed_range, signed_range}, {"curl_z", -signed_range, signed_range}};
}

// Per-channel error of storing level `level` of `tex` in `encoding`, against the float texels.
struct ChannelError {
  double max_abs = 0.0;
  double rmse = 0.0;
  double psnr_db = 0.0;  // 20 log10(1 / rmse), signal peak 1
};
std::vector<ChannelError> quantization_error(const NoiseTexture& tex, VolumeEncoding encoding, int level = 0);

// The 2023 up-rez density (seed 000, "Voxel Cloud Density Sampler Up-Rez Function"), without the
// near-camera twice-folded detail: wispy = lerp(R, G, profile); billowy = lerp(0.3 B, 0.3 A,
// profile^0.25); composite = lerp(wispy, billowy, type); density = ValueErosion(profile, composite)
// * density_scale; density = density ^ lerp(0.3, 0.6, max(eps, saturate(density_scale)^4)).
// ValueErosion is "a remap function ... as we would for 2.5D clouds" (2017: remap(base, erosion, 1,
// 0, 1)): saturate((profile - composite) / (1 - composite)).
float value_erosion(float profile, float erosion);
float uprez_density(const float noise[4], float profile, float type, float density_scale);

// Error of the up-rez density when the voxel noise is stored in `encoding` instead of float, on a test
// profile over the whole level-0 texture: profile ramps 0..1 along x, detail type 0..1 along y,
// density scale 0.25..1 along z, so every texel is evaluated once under every kind of modeling data.
struct UprezError {
  double mean_abs = 0.0;
  double max_abs = 0.0;
  double rmse = 0.0;
  double frac_above_0_05 = 0.0;  // fraction of texels whose density is off by more than 0.05
  double mean_density = 0.0;     // of the float reference, for scale
};
UprezError uprez_error(const NoiseTexture& voxel_noise, VolumeEncoding encoding);

}  // namespace cumulo::clouds
