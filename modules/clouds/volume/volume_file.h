#pragma once
// The `.nvdf` volume file: a versioned, checksummed binary form of clouds::Volume.
//
// Layout (all little endian; see volume_file.cpp for the authoritative offsets):
//   header   magic "CNVDF\r\n\x1a" (8 bytes; catches text-mode mangling), u32 version,
//            u32 header_bytes, u32 flags (bit 0: payload is zstd), u32 encoding,
//            u32 size x, y, z, u32 mip_count, u32 channel_count, f32 voxel_size,
//            f32 bounds_min[3], f32 bounds_max[3], u64 payload_bytes (uncompressed),
//            u64 stored_bytes (on disk), u64 payload_checksum (hash64 of uncompressed payload),
//            channel_count x { char name[32], char semantic[32], f32 decode_min, f32 decode_max },
//            mip_count x u64 level_bytes, u64 header_checksum (hash64 of all header bytes before it)
//   payload  stored_bytes: the levels back to back (level 0 first), zstd-compressed if flagged
//   nothing after the payload.
//
// Loading validates every field (magic, version, limits, sizes against encoding and dimensions
// with overflow-safe arithmetic, truncation, trailing bytes, both checksums, decompressed size)
// and throws cumulo::Error("<file>: <what is wrong>").
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds {

inline constexpr uint32_t kVolumeFileVersion = 1;

struct VolumeWriteOptions {
  bool compress = true;  // zstd; stored raw when compression does not make it smaller
  int zstd_level = 3;
};

struct VolumeLoadLimits {
  uint32_t max_dimension = 4096;                  // per axis
  uint64_t max_payload_bytes = 4ull << 30;        // uncompressed, all levels
};

// Serialize / parse in memory (`name` is used in error messages in place of a file name).
std::vector<uint8_t> serialize_volume(const Volume& v, const VolumeWriteOptions& opts = {});
Volume parse_volume(std::span<const uint8_t> bytes, const std::string& name, const VolumeLoadLimits& limits = {});

// Files. save_volume writes atomically (write_file_atomic).
void save_volume(const std::filesystem::path& path, const Volume& v, const VolumeWriteOptions& opts = {});
Volume load_volume(const std::filesystem::path& path, const VolumeLoadLimits& limits = {});

}  // namespace cumulo::clouds
