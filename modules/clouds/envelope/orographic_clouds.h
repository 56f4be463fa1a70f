#pragma once
// The OrographicClouds component (issue 24; the 2023 talk's "Envelope Method", seed 000): clouds that live in an
// envelope between a bottom and a top height given by 2D maps over the terrain (caps over summits, banks on the
// windward slopes, valley and sea fog), baked by bake_envelope_maps (envelope_bake.h) into EnvelopeMaps. One per level
// (the clouds module refuses a second at load, naming both).
//
//   "OrographicClouds": {
//     "extent": {"min": [-1200, -600], "max": [1200, 1600]},  // world x, z the maps cover (required, max > min)
//     "resolution": 256,      // texels per side, 16..1024; the texel is max(extent size) / resolution and the map
//                             // a square from extent.min (it may reach past extent.max on the shorter side)
//     "density": 1.0,         // density multiplier, 0..1000 (the weather scales it)
//     "coverage": 1.0,        // 0..1, multiplies every rule's and the painted coverage (baked into the maps)
//     "edge_m": 35,           // the edge gradient's width, 0.1..10000 m (the talk: remap(sample_height, 0, 35, 1, 0))
//     "wind": {"direction": [1, 0, 0.3], "speed": 4},   // the noise's scroll (pseudomotion), m/s 0..200
//     "rules": [              // after the painted maps, in order; a texel takes the union of everything covering it:
//                             // the highest coverage, and the bottom, top and detail type weighted by coverage. Every rule: "coverage" 0..1 (default 1), "detail_type" 0 wispy ..
//                             // 1 billowy (default 0.5), "variation" 0..1 (default 0) and "variation_m" (default
//                             // 200): the top's and the coverage's roughness (EnvelopeRule)
//       {"type": "cap", "center": [0, 368] | "peak", "radius_m": 350, "base_m": 180, "top_m": 520},
//           // over a summit, heights above sea level; full coverage to radius_m / 2, then smoothly 0 at radius_m;
//           // "peak": the terrain's highest texel centre inside the extent
//       {"type": "bank", "wind_from": [-1, 0, -0.3], "terrain_m": [20, 260], "base_above_terrain_m": 40,
//        "thickness_m": 220, "region": {"center": [-29, 267], "radius_m": 900}},
//           // on the windward slopes: where the ground (terrain, or sea level where higher) lies within terrain_m
//           // (fading over a quarter of the range at both ends) and rises along the wind (full weight from a rise of
//           // kBankFullSlope per metre), inside the optional region (fading over its outer fifth); heights above
//           // the ground; base_above_terrain_m defaults to 0
//       {"type": "layer", "top_m": 60, "base_above_terrain_m": 0, "below_terrain_m": 80, "region": {...}}
//           // valley or sea fog: where the terrain lies below below_terrain_m (default top_m; fading over the last
//           // kLayerFadeM metres), from the ground + base_above_terrain_m (default 0) up to top_m above sea level
//     ],
//     "maps": {"bottom": "env_bottom.png", "top": "env_top.png", "coverage": "env_coverage.png",
//              "detail": "env_detail.png", "height_range": [0, 800], "relative_to": "terrain" | "sea"}
//           // painted grey PNGs (8 or 16 bits; colour is reduced to its luminance), relative to the level file;
//           // bottom, top and height_range required, coverage (default 1) and detail (default 0.5) optional;
//           // 0..1 -> height_range, above sea level (default) or the ground; all the same size; the images span the
//           // extent rectangle, row 0 at extent.min z, column 0 at extent.min x, resampled bilinearly
//   }
//
// Everywhere the envelope keeps less than kMinThicknessM between bottom and top, it holds no cloud.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/enum_names.h"
#include "engine/core/json.h"
#include "engine/ecs/serialize.h"
#include "modules/clouds/envelope/painted_maps.h"

namespace cumulo::clouds::envelope {

inline constexpr float kMinThicknessM = 10.0f;
inline constexpr float kBankFullSlope = 0.1f;  // a 10 % rise along the wind lifts air enough for a bank
inline constexpr float kBankSlopeSpanM = 80.0f;  // ... measured over this distance (the slope, not the ground's roughness)
inline constexpr float kLayerFadeM = 20.0f;

struct CapRule {
  bool at_peak = false;    // "center": "peak"
  glm::vec2 center{0.0f};  // world x, z (resolved to the peak by the bake when at_peak)
  float radius_m = 100.0f;
  float base_m = 0.0f, top_m = 100.0f;  // above sea level
};

struct BankRule {
  glm::vec3 wind_from{-1.0f, 0.0f, 0.0f};  // where the wind comes from; only x, z count
  glm::vec2 terrain_m{0.0f, 100.0f};
  float base_above_terrain_m = 0.0f;
  float thickness_m = 100.0f;
};

struct LayerRule {
  float top_m = 50.0f;  // above sea level
  float base_above_terrain_m = 0.0f;
  float below_terrain_m = 50.0f;
};

struct EnvelopeRegion {
  glm::vec2 center{0.0f};
  float radius_m = 1.0f;
};

enum class RuleType { Cap, Bank, Layer };  // the variant's index
inline constexpr std::array kRuleTypeNames{EnumName<RuleType>{RuleType::Cap, "cap"},
                                           EnumName<RuleType>{RuleType::Bank, "bank"},
                                           EnumName<RuleType>{RuleType::Layer, "layer"}};

struct EnvelopeRule {
  std::variant<CapRule, BankRule, LayerRule> kind;
  float coverage = 1.0f;
  float detail_type = 0.5f;
  // The authored heights' roughness: a 2D fBm of features variation_m across lifts and lowers the top by up to
  // `variation` of the thickness and thins the coverage where it lowers it (0: the rule's smooth envelope).
  float variation = 0.0f;
  float variation_m = 200.0f;
  std::optional<EnvelopeRegion> region;  // bank and layer
  std::string where;                     // its JSON path, for later messages
  RuleType type() const { return RuleType(kind.index()); }
};

struct PaintedMapFile {
  std::string path;   // as written; empty: absent
  std::string where;  // its JSON path
};

struct PaintedMapSet {
  PaintedMapFile bottom, top, coverage, detail;
  glm::vec2 height_range{0.0f, 1000.0f};
  bool relative_to_terrain = false;
};

struct OrographicClouds {
  glm::vec2 extent_min{0.0f}, extent_max{0.0f};  // world x, z
  uint32_t resolution = 256;
  float density = 1.0f;
  float coverage = 1.0f;
  float edge_m = 35.0f;
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;
  std::vector<EnvelopeRule> rules;
  std::optional<PaintedMapSet> maps;
  std::string where;  // "level.json: $.entities[3].components.OrographicClouds", for later messages
  // Filled when the level loads (resolve_orographic_clouds): the level's folder and the decoded maps.
  std::filesystem::path level_dir;
  std::shared_ptr<const PaintedMaps> painted;
};

OrographicClouds orographic_clouds_from_json(const JsonView& v);
Json orographic_clouds_to_json(const OrographicClouds& c);
void register_orographic_clouds_component(ecs::ComponentRegistry& registry);

// Reads the painted maps (paths relative to level_dir) into c.painted and keeps level_dir; a missing, unreadable or
// mismatched PNG throws cumulo::Error naming its JSON path and the file. Nothing to do without "maps".
void resolve_orographic_clouds(OrographicClouds& c, const std::filesystem::path& level_dir);
// The same decode without a component (the bake's fallback when nothing resolved them).
PaintedMaps load_painted_maps(const PaintedMapSet& maps, const std::filesystem::path& level_dir);

}  // namespace cumulo::clouds::envelope
