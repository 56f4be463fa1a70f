#pragma once
// Exact Euclidean distance transform on a voxel grid (Felzenszwalb & Huttenlocher 2012, "Distance
// Transforms of Sampled Functions": a 1D lower envelope of parabolas per axis, O(n) per line, so the
// 3D transform is linear in the voxel count and runs on all cores). The importers use it to turn a
// thresholded density (or the sign of a level set beyond its narrow band) into the field NVDF's SDF.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds {

// Squared distance, in voxels^2, from each voxel centre to the nearest voxel with mask != 0
// (0 on such voxels; +inf where the mask is empty). x fastest, then y, then z.
std::vector<float> squared_distance_to_mask(const std::vector<uint8_t>& mask, glm::uvec3 size);

// Signed distance in metres from `inside` (nonzero = inside the cloud): positive outside, negative
// inside. The surface is taken halfway between an inside and an outside voxel centre, so a voxel
// next to the surface reads +-voxel_size/2. An all-outside (all-inside) grid yields +inf (-inf).
std::vector<float> signed_distance_from_mask(const std::vector<uint8_t>& inside, glm::uvec3 size, float voxel_size);

}  // namespace cumulo::clouds
