#pragma once
// The field NVDF's signed distance (2023 talk: "we generate a 3d signed distance field and write it
// out as a separate NVDF. The data is originally ranged from -256 to 4096 but we scale it to a zero to
// 1 range"), and the dimensional profile derived from it.
//
// Construction: the composed recipe field (soft-min blends, erosion, squash and shear make it only an
// estimate of distance) decides inside/outside per voxel. Away from the surface the distance is the
// EXACT Euclidean distance between voxel centres of opposite sign (Felzenszwalb-Huttenlocher, edt.h)
// minus half a voxel (the surface lies between the two centres). On voxels with a 6-neighbour of the
// other sign, the analytic value divided by its gradient length (a first-order distance to the
// zero set, sub-voxel accurate) replaces it when smaller in magnitude.
#include <cstdint>
#include <vector>

#include "modules/clouds/bake/compose.h"
#include "modules/clouds/bake/recipe.h"

namespace cumulo::clouds::bake {

inline constexpr float kFieldMin = -256.0f;  // metres (the talk's range)
inline constexpr float kFieldMax = 4096.0f;

struct FieldStats {
  uint64_t inside_voxels = 0;
  uint64_t surface_voxels = 0;  // voxels that took the analytic sub-voxel distance
};

// Signed distance in metres, clamped to [kFieldMin, kFieldMax], one per voxel of `grid`.
// `progress` (optional) advances by 1 after each of its three steps (two EDTs, the combination).
std::vector<float> build_field(const std::vector<float>& composed, const BakeGrid& grid, FieldStats* stats = nullptr,
                               Progress* progress = nullptr);

// 16-bit storage of the 0..1 range, rounded DOWN so the stored value never exceeds the distance.
inline uint16_t field_to_unorm16(float metres) {
  double v = (static_cast<double>(metres) - kFieldMin) / (kFieldMax - kFieldMin);
  v = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
  return static_cast<uint16_t>(v * 65535.0);  // truncation = floor for v >= 0
}
inline float unorm16_to_field(uint16_t q) { return kFieldMin + (kFieldMax - kFieldMin) * (q / 65535.0f); }

// Dimensional profile: saturate(-sdf / depth) ^ exponent (0 outside, rising with depth below the surface).
float profile_from_field(float sdf_m, const ProfileParams& p);

}  // namespace cumulo::clouds::bake
