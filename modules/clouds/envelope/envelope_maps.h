#pragma once
// The Envelope method's baked 2D data (issue 24; the 2023 talk's "Envelope Method", seed 000): what the
// march (shaders/clouds/envelope_march.comp), the path tracer and the CPU density query read. Built by
// bake_envelope_maps (envelope_bake.h) from an OrographicClouds component (orographic_clouds.h).
//
// Texel (i, j) covers world x in origin.x + [i, i + 1) * texel_m (z likewise with j; row j = z).
//
// `shape` (sampled bilinearly for the density):
//   x: the envelope's bottom, world y (m)   y: its top, world y (m)
//   z: coverage 0..1 (0: no envelope)      w: detail type 0 wispy .. 1 billowy
//   Texels outside the footprint hold their nearest covered texel's bottom and top (so bilinear filtering
//   at the footprint's side never mixes in a meaningless height) with coverage 0.
// `steps` (fetched unfiltered, nearest texel, for the sample placement; every value conservative for any
// point inside the texel and for the bilinear density around it):
//   x: the conservative top Tc: the highest top over the texel's 3x3 neighbourhood where coverage > 0 there
//      (the dilated tops of the 3x3's empty texels count too: the bilinear top mixes them in);
//      kEmptyTop where none (no density above it in the texel's column)
//   y: the conservative bottom Bc: the lowest bottom over the 3x3 where coverage > 0 (dilated bottoms included);
//      kEmptyBottom where none
//   z: the top cone ratio (Dummer 2006: horizontal distance per metre of height) of the cone whose apex stands at
//      the top apex Ht(i) (`apex`.x): for every texel k with Tc(k) > Ht(i), dist(i, k) >= z * (Tc(k) - Ht(i)),
//      dist being the smallest distance between points of the two texels' squares (per axis max(0, |offset| - 1)
//      texels); capped at kMaxConeRatio. A point of the texel above Ht(i) may step along a ray to where it leaves the
//      upward cone rooted there: nothing with density lies inside it.
//   w: the bottom cone ratio, the same for the downward cone under the bottom apex Hb(i) (for every k with
//      Bc(k) < Hb(i), dist >= w * (Hb(i) - Bc(k))).
// `apex` (fetched unfiltered): x: Ht(i), the highest Tc over the texel's 3x3; y: Hb(i), the lowest Bc over it. Rooted
//   there rather than at Tc(i), a cone has no neighbour above its apex (the squares of neighbours touch, so a higher
//   neighbour would close every cone rooted at Tc(i) on a slope); between Tc(i) and Ht(i) the march takes small steps.
// `distance_m` (fetched unfiltered): a lower bound of the horizontal distance from any point of the texel to
//   any point of a texel whose 3x3 neighbourhood holds coverage (0 on and next to the footprint): the
//   distance step. kFarDistanceM where there is no envelope at all.
// `edge_m` (bilinear): the horizontal distance from the texel's centre to the footprint's side, > 0 inside
//   (the edge gradient's input), < 0 outside: the distance to the nearest centre across the side minus half a
//   texel (the map's border is a side); -kFarDistanceM where there is no envelope at all.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds::envelope {

inline constexpr float kEmptyTop = -1.0e4f;
inline constexpr float kEmptyBottom = 1.0e5f;
inline constexpr float kMaxConeRatio = 64.0f;
inline constexpr float kFarDistanceM = 1.0e6f;

struct EnvelopeMaps {
  uint32_t resolution = 0;  // texels per side
  glm::vec2 origin{0.0f};   // world x, z of texel (0, 0)'s corner
  float texel_m = 1.0f;     // a texel's side in metres
  float min_bottom = 0.0f, max_top = 0.0f;  // over covered texels (world y); 0, 0 when none
  float edge_width_m = 35.0f;               // the edge gradient's width (OrographicClouds::edge_m)
  std::vector<glm::vec4> shape;  // resolution^2, row j = z
  std::vector<glm::vec4> steps;
  std::vector<float> distance_m;
  std::vector<float> edge_m;
  std::vector<glm::vec2> apex;
  bool empty() const { return shape.empty(); }
  glm::vec2 size() const { return glm::vec2(float(resolution) * texel_m); }
};

}  // namespace cumulo::clouds::envelope
