#pragma once
// Exact Euclidean distance transform on a voxel grid (Felzenszwalb & Huttenlocher 2012, "Distance
// Transforms of Sampled Functions", Theory of Computing: a 1D lower envelope of parabolas per axis,
// O(n) per line, so the 3D transform is linear in the voxel count and runs on all cores). Exact up to
// float rounding, not a chamfer approximation. The importers use it to turn a thresholded density (or
// the sign of a level set beyond its narrow band) into the field NVDF's SDF; the bake uses it with
// per-axis spacing for its far-field distances.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds {

// Squared distance where there is no site at all: +inf. Callers that subtract or interpolate such
// values must handle it (inf - inf is NaN); sqrt, min, max, clamp and comparisons are safe.
inline constexpr float kNoSiteDistance2 = std::numeric_limits<float>::infinity();

// 1D pass: d[p] = min_q ((p - q)^2 * spacing^2 + f[q]) for p, q in [0, n); f may hold kNoSiteDistance2
// (all of it: d is then all kNoSiteDistance2). `v` (n ints) and `z` (n + 1 doubles) are scratch.
void squared_distance_1d(const float* f, uint32_t n, float spacing, float* d, int* v, double* z);

// Squared distance from each voxel centre to the nearest voxel with mask != 0 (0 on such voxels;
// kNoSiteDistance2 everywhere if the mask is empty). x fastest, then y, then z. `spacing` is the voxel
// pitch along each axis: the default {1,1,1} gives voxels^2, metres per voxel give metres^2.
std::vector<float> squared_distance_to_mask(const std::vector<uint8_t>& mask, glm::uvec3 size,
                                            glm::vec3 spacing = glm::vec3(1.0f));

// Signed distance in metres from `inside` (nonzero = inside the cloud): positive outside, negative
// inside. The surface is taken halfway between an inside and an outside voxel centre, so a voxel
// next to the surface reads +-voxel_size/2. An all-outside (all-inside) grid yields +inf (-inf).
std::vector<float> signed_distance_from_mask(const std::vector<uint8_t>& inside, glm::uvec3 size, float voxel_size);

}  // namespace cumulo::clouds
