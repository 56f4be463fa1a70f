#pragma once
// From a grown cloud to the talk's modeling attributes (2023 talk, "Voxel Cloud Modeling": the
// dimensional profile "generated from a signed-distance field of the cloud", detail type "used to blend
// from wispy to billowy noise details", density scale "used to decrease density after the noise was
// applied"), all in the grown cloud's local frame, ready for a recipe's "grown" edit:
//
//  - signed distance to the cloud-water iso-surface: the cloud water is resampled (trilinear) to at
//    most 8 m cells, thresholded, and the exact EDT of the mask gives the distance; next to the
//    surface the linear iso-crossing (iso - qc) / |grad qc| replaces it (sub-cell accurate);
//  - profile depth: the metres below the surface at which the profile reaches 1, following the cloud's
//    local thickness: k x the deepest interior point within kThicknessRadius, clamped to
//    [kMinProfileDepth, kMaxProfileDepth] (a thin sheet reaches 1 in its middle, a tower's core at the
//    talk-scale ramp);
//  - detail type: "layered wisps and curly distortions form where density is decreasing and layered
//    billows occur where density is increasing" (talk): 0.5 + 0.5 x ((1 - kHeightWeight) x rates +
//    kHeightWeight x (2 h - 1)), rates = kGrowthWeight d(qc)/dt + kCondensationWeight condensation +
//    kUpdraftWeight w, each over its 90th percentile in the cloud, h the height within the cloud's column
//    (0 base, 1 top); clamped, then blurred over one cell: the cloud growing into the air (rising tops,
//    towers) is billowy; retreating and evaporating cloud (flanks, a decaying cloud) and bases wispy;
//  - density scale: lower where the cloud is thin (cloud water under its median) or evaporating.
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "modules/clouds/bake/grow/grown_cloud.h"

namespace cumulo::clouds::grow {

inline constexpr float kThicknessRadius = 64.0f;   // game metres
inline constexpr float kThicknessFactor = 0.8f;
inline constexpr float kMinProfileDepth = 12.0f;   // metres
inline constexpr float kMaxProfileDepth = 96.0f;   // the recipes' default ramp
inline constexpr float kGrowthWeight = 0.6f;
inline constexpr float kCondensationWeight = 0.25f;
inline constexpr float kUpdraftWeight = 0.15f;
// Share of the detail type from the height within the cloud's column (bases wispy, tops billowy); the rest from the rates.
inline constexpr float kHeightWeight = 0.5f;

// A scalar grid in local metres; sample() is trilinear and clamps to the edge values.
struct AttributeGrid {
  glm::uvec3 dims{0};
  glm::vec3 origin{0.0f};  // local position of sample (0, 0, 0)
  float spacing = 8.0f;
  std::vector<float> values;
  float sample(glm::vec3 p) const;
};

struct GrownModeling {
  AttributeGrid sdf;            // metres, negative inside; beyond the grid: distance to the box + edge value
  AttributeGrid profile_depth;  // metres
  AttributeGrid detail_type;    // 0 wispy .. 1 billowy
  AttributeGrid density_scale;  // 0..1
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // local box of the grids
  float signed_distance(glm::vec3 p) const;       // sdf continued outside the box
};

std::shared_ptr<const GrownModeling> derive_modeling(const GrownCloud& g);

}  // namespace cumulo::clouds::grow
