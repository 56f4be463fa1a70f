#pragma once
// BC1, the one codec for every volume that stores it: the exact decode (and the ways GPUs differ),
// Hugh Malan's conservative scalar encoding of the field NVDF's signed distance, its verifier, and a
// plain RGB encoder for the modeling NVDF. Volume::texel(), the baker and `cumulo import` all use it.
//
// Index:  Bc1Model  bc1_expand  bc1_palette  bc1_decode_texel_model  bc1_decode_texel  (decode)
//         kSdfUnpackDot  sdf_endpoint_round_down  encode_sdf_bc1  verify_sdf_bc1  (conservative scalar)
//         encode_rgb_bc1  (modeling)
//
// The exact decode (Khronos Data Format Specification, "S3TC compressed texture image formats",
// BC1 / VK_FORMAT_BC1_RGB_UNORM_BLOCK; Direct3D "Block Compression"): each 565 endpoint is widened to
// 8 bits by bit replication (r8 = r5 << 3 | r5 >> 2, g8 = g6 << 2 | g6 >> 4), and when color0 > color1
// (as 16-bit integers) the palette is {c0, c1, 2/3 c0 + 1/3 c1, 1/3 c0 + 2/3 c1} in exact arithmetic;
// otherwise {c0, c1, (c0 + c1) / 2, black}. Hardware is allowed to round the interpolated entries
// (fgiesen 2021, "GPU BCn decoding": AMD uses 43/64 and 21/64 weights, others round or truncate to
// 8 bits), so the conservative encoder bounds every entry by the largest of those models.
//
// The scalar unpack (2023 talk, bonus slide): a 16-bit value split as 5:6:5 over R, G, B and rebuilt
// with one dot product. The talk's float3(1.0, 0.03529415, 0.00069204) is exactly
// (1, 9/255, 9/255 * 5/255): after bit replication consecutive R levels are 8 or 9 / 255 apart, so G
// (0..1) must be scaled to cover the largest R step, 9/255; consecutive G levels are 4 or 5 / 255
// apart, so B covers the largest G step times G's weight, 5/255 * 9/255. With those weights, rounding
// R down, then G, then B ("sFindLowerBoundIndex") always leaves a residual the next channel can
// absorb, giving about 16 bits of precision from a 0.5 byte/texel format.
// In a shader: metres = -256.0 + 4352.0 * dot(texture(field_bc1, uvw).rgb, vec3(1.0, 9.0/255.0, 45.0/65025.0)).
//
// What is guaranteed (and tested exhaustively by verify_sdf_bc1):
//  - every texel decodes, under each Bc1Model, to at most its 16-bit value, which is itself the float
//    distance rounded down; so a texel never reads farther than the baked distance;
//  - the unpack is linear, so filtering then unpacking equals unpacking then filtering: any bilinear or
//    trilinear filter (non-negative weights summing to 1, in exact arithmetic) of the BC1 texture is
//    at most the same filter of the 16-bit texture. The verifier checks the edge midpoints and the
//    cell centres explicitly.
// Not covered: (a) between texels, a filtered distance can exceed the true continuous distance even
// for the 16-bit texture (interpolating a 1-Lipschitz function overestimates by up to sqrt(3)/2 voxel
// in empty space); the ray-march's max(sdf, adaptive step) tolerates that, as in the talk. (b) Texture
// units that round the filtered 8-bit channels up (not truncate) can add up to half an 8-bit step of R.
// Measured on the sample (512 x 64 x 512): mean 2.24 m, max 18.9 m below the 16-bit value; with
// only the Exact model honoured the mean would be 1.68 m (the cost of being safe on every GPU).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo {
class Progress;
}

namespace cumulo::clouds {

// How a decoder computes BC1's interpolated palette entries from the 8-bit endpoints a, b.
enum class Bc1Model {
  Exact,  // (2a + b) / 3 in real arithmetic: the specification
  Round,  // (2a + b + 1) / 3 in integers: round to nearest 8-bit value
  Floor,  // (2a + b) / 3 in integers: truncation (Mesa's software decoder)
  Amd,    // (43a + 21b + 32) >> 6 (fgiesen 2021)
};
inline constexpr Bc1Model kBc1Models[] = {Bc1Model::Exact, Bc1Model::Round, Bc1Model::Floor, Bc1Model::Amd};

// 565 -> 8-bit channels by bit replication, as 0..255 integers.
glm::ivec3 bc1_expand(uint16_t c);
// The four palette colours (0..1 per channel) of endpoints c0, c1 under `model`.
void bc1_palette(uint16_t c0, uint16_t c1, Bc1Model model, glm::dvec3 out[4]);
// Decodes texel (tx, ty) of an 8-byte block to RGB 0..1.
glm::dvec3 bc1_decode_texel_model(const uint8_t* block, uint32_t tx, uint32_t ty, Bc1Model model);
// The reference decode (Bc1Model::Exact) as RGBA 0..1: alpha is 0 for the black entry of the
// three-colour mode (c0 <= c1, index 3), else 1. What Volume::texel() returns for BC1.
glm::vec4 bc1_decode_texel(const uint8_t* block, uint32_t tx, uint32_t ty);

// ---- Conservative scalar (field NVDF) -----------------------------------------------------------
// decoded = dot(rgb, kSdfUnpackDot) in 0 .. 1.0360; the field's 0..1 maps to -256..4096 m.
inline constexpr double kSdfDotG = 9.0 / 255.0;
inline constexpr double kSdfDotB = 9.0 / 255.0 * 5.0 / 255.0;
inline const glm::dvec3 kSdfUnpackDot{1.0, kSdfDotG, kSdfDotB};
inline double sdf_unpack(glm::dvec3 rgb) { return glm::dot(rgb, kSdfUnpackDot); }

// The largest 565 colour whose exact decode is <= v (v >= 0): R rounded down, then G, then B.
uint16_t sdf_endpoint_round_down(double v);

// Encodes a field of 16-bit values (0..65535 <-> 0..1; x fastest, then y, then z) into BC1 blocks
// in the volume layout (per z slice, 4x4 blocks over x and y, row-major). Every texel decodes, under
// every Bc1Model, to at most its 16-bit value (minus a float32 dot-product margin).
// `progress` (optional) advances by one per 4x4 block.
std::vector<uint8_t> encode_sdf_bc1(const std::vector<uint16_t>& values, glm::uvec3 dims, Progress* progress = nullptr);

struct Bc1SdfReport {
  uint64_t texels = 0;
  uint64_t violations = 0;           // texels decoding above their value under some model (must be 0)
  uint64_t midpoint_checks = 0;      // edge midpoints and cell centres (bilinear / trilinear filtering)
  uint64_t midpoint_violations = 0;  // filtered decode above the filtered 16-bit values (must be 0)
  double mean_error_m = 0.0;         // 16-bit value minus exact decode, metres
  double max_error_m = 0.0;
  double mean_error_vs_float_m = 0.0;  // float field minus exact decode, metres (needs `reference`)
  double max_error_vs_float_m = 0.0;
};

// Decodes every texel under every model and checks it against `values`; checks filtered midpoints.
// `reference` (optional, metres) adds the error against the unquantized field.
Bc1SdfReport verify_sdf_bc1(const std::vector<uint8_t>& blocks, const std::vector<uint16_t>& values, glm::uvec3 dims,
                            const std::vector<float>* reference = nullptr);

// ---- Plain RGB (modeling NVDF) -------------------------------------------------------------------
// rgb: 3 floats per texel in 0..1 (x fastest); weights: per-channel importance in the error metric.
std::vector<uint8_t> encode_rgb_bc1(const std::vector<float>& rgb, glm::uvec3 dims, glm::vec3 weights,
                                    Progress* progress = nullptr);

struct Bc1RgbReport {
  glm::dvec3 rmse{0.0};
  glm::dvec3 max_error{0.0};
};
Bc1RgbReport measure_rgb_bc1(const std::vector<uint8_t>& blocks, const std::vector<float>& rgb, glm::uvec3 dims);

}  // namespace cumulo::clouds
