#pragma once
// The envelope's step data (envelope_maps.h), derived from its shape alone: what bake_envelope_maps runs once the
// rules and painted maps are united, and what the tests check against brute force.
//
//   distance_transform: exact squared Euclidean distances between texel centres to the nearest site, with that
//     site's index (Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions", 2012: two passes of
//     the 1D lower envelope of parabolas), O(n^2) for an n x n grid.
//   cone_ratios: the header's exact cone ratio per texel, a branch and bound over a max pyramid of the values: a
//     block is skipped when its highest value is not above the texel's or when the ratio bound from its nearest
//     point and its highest value cannot beat the best ratio found so far; blocks are visited nearest first. Every
//     pair's ratio is bounded by the same rounding as the leaf's own, so the minimum is the brute force's.
#include <cstdint>
#include <vector>

#include "modules/clouds/envelope/envelope_maps.h"

namespace cumulo::clouds::envelope {

struct DistanceField {
  std::vector<double> d2;        // squared distance in texels; kNoSite where there is no site at all
  std::vector<int32_t> nearest;  // the nearest site's index (row j = z: j * n + i); -1 where none
};
inline constexpr double kNoSite = 1.0e30;
DistanceField distance_transform(const std::vector<uint8_t>& site, uint32_t n);

// For each texel i: min over texels k with value(k) > apex(i) of dist(i, k) / (value(k) - apex(i)), dist = the
// smallest distance between the two texels' squares (per axis max(0, |offset| - 1) texels, times texel_m); `cap`
// where none or above. Rounded down with a relative margin of 1e-6 so that dist >= ratio * difference holds for every
// pair in float and double arithmetic.
std::vector<float> cone_ratios(const std::vector<float>& apex, const std::vector<float>& value, uint32_t n, float texel_m,
                               float cap);

// From maps.shape (heights of covered texels, coverage; resolution and texel_m set): the dilation of the heights,
// edge_m, steps, distance_m, min_bottom and max_top.
void derive_envelope_steps(EnvelopeMaps& maps);

}  // namespace cumulo::clouds::envelope
