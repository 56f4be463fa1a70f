#pragma once
// `cumulo noise -o DIR [--seed N] [--size N] [--format 4|8|both] [--no-previews]`: generates every cloud
// noise texture and writes them as .nvdf volumes (clouds/volume) with PNG previews:
//   voxel_noise.nvdf          2023 voxel-cloud noise, 4 channels, full mips; RGBA8 by default, the
//                             talk's 4-bit R4G4B4A4 with --format 4
//                             (--format both also writes voxel_noise_r4g4b4a4.nvdf and voxel_noise_rgba8.nvdf)
//   sky_noise_base.nvdf       2015 128^3 RGBA8: Perlin-Worley + 3 Worley fBm
//   sky_noise_detail.nvdf     2015 32^3 RGB Worley fBm (stored RGBA8, alpha unused)
//   curl_noise.nvdf           2015 128^2 RGB curl (RGBA8, 1 texel deep; decode range = +-max |curl|)
//   *_preview.png             slice z = 0 of each, channels side by side, tiled 2x2
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/command.h"
#include "modules/clouds/noise/noise_encode.h"

namespace cumulo::clouds {

// The voxel noise's default GPU format (see noise_command.cpp for the measurements behind it).
inline constexpr VolumeEncoding kVoxelNoiseEncoding = VolumeEncoding::RGBA8;

enum class NoiseFormat { Bits4, Bits8, Both };

struct NoiseSetOptions {
  std::filesystem::path out_dir;
  uint64_t seed = 1;
  int size = 128;  // voxel noise, sky base and curl; the sky detail texture is size / 4 (min 4)
  NoiseFormat format = kVoxelNoiseEncoding == VolumeEncoding::R4G4B4A4 ? NoiseFormat::Bits4 : NoiseFormat::Bits8;
  bool previews = true;
  bool measure = true;   // quality of 4 vs 8 bits (PSNR, max error, up-rez density error)
  bool progress = true;  // Progress lines (they print only on a terminal anyway)
};

struct NoiseFileInfo {
  std::filesystem::path path;
  std::string encoding;
  uint32_t width = 0, height = 0, depth = 0, mips = 0, channels = 0;
  uint64_t gpu_bytes_level0 = 0;  // texel payload of level 0
  uint64_t gpu_bytes = 0;         // all mips
  uint64_t file_bytes = 0;
};

struct NoiseQuality {
  std::string encoding;
  std::vector<ChannelError> channels;  // level 0
  UprezError uprez;
};

struct NoiseSetReport {
  std::vector<NoiseFileInfo> files;
  std::vector<NoiseQuality> voxel_quality;  // empty unless measured
  double generate_seconds = 0.0;            // noise evaluation + mips, all textures
  double total_seconds = 0.0;               // including encoding, measuring and writing
};

NoiseSetReport write_noise_set(const NoiseSetOptions& options);
std::string format_noise_report(const NoiseSetReport& report);

void register_noise_command(CommandRegistry& registry);

}  // namespace cumulo::clouds
