#pragma once
// Exact Euclidean distance transform (Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled
// Functions", Theory of Computing 2012): the squared distance from every voxel centre to the nearest
// "site" voxel centre, computed as three separable 1D lower-envelope-of-parabolas passes, O(n) per
// line, on all cores. Exact (up to float rounding), not a chamfer or brute-force approximation.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds::bake {

// Squared distance of "no site at all".
inline constexpr float kEdtInfinity = 1.0e30f;

// 1D pass: d[p] = min_q ((p - q)^2 * spacing^2 + f[q]) for p, q in [0, n). f may hold kEdtInfinity.
// `v` (int, n) and `z` (double, n + 1) are scratch.
void edt_1d(const float* f, int n, float spacing, float* d, int* v, double* z);

// sites: dims.x * dims.y * dims.z flags (x fastest); spacing: metres per voxel along each axis.
// Returns squared metres to the nearest site (kEdtInfinity when there is no site).
std::vector<float> squared_edt(const std::vector<uint8_t>& sites, glm::uvec3 dims, glm::vec3 spacing);

}  // namespace cumulo::clouds::bake
