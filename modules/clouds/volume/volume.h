#pragma once
// In-memory volume: the common form of every 3D asset the cloud module stores (modeling NVDF,
// field NVDF, 3D noises). A volume is a box in the world (bounds, metres) sampled on a regular grid
// (size, voxel size), holding 1-4 logical channels in one texel encoding, with a mip chain.
//
// Index:
//   VolumeEncoding      texel layouts (unorm, float, packed 4:4:4:4, BC1 blocks)
//   VolumeChannel       a channel's name, semantic and decode range (e.g. SDF 0..1 <-> -256..4096 m)
//   Volume              the volume itself, with texel accessors and validation
//   generate_mips()     box-filtered 3D mip chain for the non-block encodings
//   bc1_blocks()        block layout (the BC1 codec itself: bc1.h)
//
// Layout of a level's payload: x fastest, then y, then z ("slice"). BC1: per z slice, 4x4 texel
// blocks of 8 bytes each in row-major block order (the layout a 3D BC1 texture has in Vulkan).
// 3D mips halve all three axes (min 1), as a GPU 3D texture's do.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds {

// Channel semantics shared by the baker, the importer and the renderer (2023 talk, "NVDF's").
inline constexpr std::string_view kDimensionalProfile = "dimensional_profile";
inline constexpr std::string_view kDetailType = "detail_type";
inline constexpr std::string_view kDensityScale = "density_scale";
// The weather coverage a voxel's cloud needs (bake/recipe.h Edit::coverage; the ramp is CLOUD_COVERAGE_RAMP in
// shaders/shared/cloud_params.h): the modeling NVDF's alpha, and coverage.nvdf's one channel.
inline constexpr std::string_view kCoverageThreshold = "coverage_threshold";
inline constexpr std::string_view kSignedDistance = "sdf";
inline constexpr std::string_view kNoise = "noise";

// The field NVDF's signed distance range in metres (2023 talk: "originally ranged from -256 to 4096
// but we scale it to a zero to 1 range").
inline constexpr float kSdfRangeMin = -256.0f;
inline constexpr float kSdfRangeMax = 4096.0f;

// Values are part of the file format: never renumber.
enum class VolumeEncoding : uint32_t {
  R8 = 1,        // 1 x unorm8
  RG8 = 2,       // 2 x unorm8
  RGBA8 = 3,     // 4 x unorm8
  R16 = 4,       // 1 x unorm16 (little endian)
  RGBA16 = 5,    // 4 x unorm16
  R32F = 6,      // 1 x float32
  R4G4B4A4 = 7,  // 16-bit word, Vulkan R4G4B4A4_UNORM_PACK16 order: R bits 12-15, G 8-11, B 4-7, A 0-3
  BC1 = 8,       // 4x4 blocks per z slice, 8 bytes each: RGB (+1-bit alpha), 565 endpoints
  BC4 = 9,       // 4x4 blocks per z slice, 8 bytes each: one unorm channel, 8-bit endpoints
  BC7 = 10,      // 4x4 blocks per z slice, 16 bytes each: RGBA (stored only; texel() cannot decode it)
};

const char* encoding_name(VolumeEncoding e);
// Parses the names encoding_name() returns ("r8", "rgba8", "bc1", ...); false if unknown.
bool parse_encoding(std::string_view name, VolumeEncoding* out);
bool is_valid_encoding(uint32_t value);
// Components a texel decodes to (BC1: 4, RGB + alpha; BC4: 1; BC7: 4).
uint32_t encoding_components(VolumeEncoding e);
bool is_block_encoding(VolumeEncoding e);
// Bytes per texel for non-block encodings; 0 for block encodings.
uint32_t encoding_texel_bytes(VolumeEncoding e);
// Bytes per 4x4 block for block encodings; 0 otherwise.
uint32_t encoding_block_bytes(VolumeEncoding e);
// Bytes of one level of size (x, y, z), or UINT64_MAX when that does not fit (callers check
// limits first; the arithmetic is overflow-safe for any uint32 input).
uint64_t encoded_level_bytes(VolumeEncoding e, glm::uvec3 size);
// Size of mip level `level` of a volume of size `base`: every axis halves, minimum 1.
glm::uvec3 mip_level_size(glm::uvec3 base, uint32_t level);
// Number of levels in a full chain down to 1x1x1.
uint32_t full_mip_count(glm::uvec3 base);

struct VolumeChannel {
  std::string name;      // free text for tools, e.g. "r" or "profile" (at most 31 bytes in a file)
  std::string semantic;  // kDimensionalProfile, kSignedDistance, ... (at most 31 bytes in a file)
  // A stored value v in 0..1 (unorm) means decode_min + v * (decode_max - decode_min).
  // Identity (0, 1) for plain data; for R32F the stored value is already the decoded one.
  float decode_min = 0.0f;
  float decode_max = 1.0f;
};

struct Volume {
  glm::uvec3 size{0};           // texels at level 0
  float voxel_size = 1.0f;      // metres per texel at level 0
  glm::vec3 bounds_min{0.0f};   // world box, metres
  glm::vec3 bounds_max{0.0f};
  VolumeEncoding encoding = VolumeEncoding::R8;
  std::vector<VolumeChannel> channels;      // 1..encoding_components(encoding)
  std::vector<std::vector<uint8_t>> levels;  // levels[0] is full resolution; each encoded_level_bytes()

  // Allocates `mip_count` zeroed levels for the given size/encoding (bounds default to
  // [0, size * voxel_size]).
  static Volume create(glm::uvec3 size, float voxel_size, VolumeEncoding encoding,
                       std::vector<VolumeChannel> channels, uint32_t mip_count = 1);

  uint32_t mip_count() const { return static_cast<uint32_t>(levels.size()); }
  glm::uvec3 level_size(uint32_t level) const { return mip_level_size(size, level); }
  uint64_t level_bytes(uint32_t level) const { return encoded_level_bytes(encoding, level_size(level)); }
  uint64_t payload_bytes() const;  // sum over levels

  // Index of the channel with this semantic, or -1.
  int find_channel(std::string_view semantic) const;
  // Same, but throws cumulo::Error naming `what` (e.g. the file) when missing.
  uint32_t channel(std::string_view semantic, std::string_view what) const;

  // Stored component value as float: unorm -> 0..1, R32F -> as stored, BC1/BC4 -> reference
  // decode (bc1.h: bc1_decode_texel); BC7 throws. `c` indexes components, not only declared channels.
  float texel(uint32_t x, uint32_t y, uint32_t z, uint32_t c, uint32_t level = 0) const;
  // texel() mapped through the channel's decode range (R32F: returned as stored).
  float decoded(uint32_t x, uint32_t y, uint32_t z, uint32_t c, uint32_t level = 0) const;
  // Stores a 0..1 value (clamped, rounded to nearest) for unorm encodings, or the raw value for
  // R32F. Not for BC1 (throws): block encoders write levels[] directly.
  void set_texel(uint32_t x, uint32_t y, uint32_t z, uint32_t c, float value, uint32_t level = 0);
  // Maps a decoded value (e.g. metres) into the channel's 0..1 range and stores it.
  void set_decoded(uint32_t x, uint32_t y, uint32_t z, uint32_t c, float value, uint32_t level = 0);

  // Throws cumulo::Error("<what>: ...") if fields and payload sizes disagree (used by the writer
  // and the loader so that no inconsistent volume reaches a file or the GPU).
  void validate(std::string_view what) const;
};

// A GPU sampler's trilinear fetch of component `c` (texel(), level 0) at normalized `uvw` (texel centres at
// (i + 0.5) / n): clamp-to-edge, or repeat for tiling noise. The CPU side of a density the GPU samples.
float sample_trilinear(const Volume& v, glm::vec3 uvw, uint32_t c, bool repeat);

// Replaces levels[1..] with a box-filtered chain of `mip_count` levels in total (0: full chain).
// Averages in the stored 0..1 (or float) domain, so every encoding but BC1 is supported; BC1
// volumes must be mipped before encoding. For tiling noise, wrap = true filters with wrap-around
// at odd sizes; otherwise the edge texel is repeated.
void generate_mips(Volume& v, uint32_t mip_count = 0, bool wrap = false);

// Block helpers. Block (bx, by) of slice z in a level of size s starts at
// ((z * bc1_blocks(s.y) + by) * bc1_blocks(s.x) + bx) * encoding_block_bytes(e).
inline uint32_t bc1_blocks(uint32_t texels) { return (texels + 3) / 4; }
// BC4 unorm: 8-bit endpoints r0, r1; 8-entry palette if r0 > r1, else 6 entries + 0 and 1.
float bc4_decode_texel(const uint8_t* block, uint32_t tx, uint32_t ty);

}  // namespace cumulo::clouds
