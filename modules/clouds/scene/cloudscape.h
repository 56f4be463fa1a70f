#pragma once
// The Cloudscape component (issue 8): a baked voxel cloudscape placed by its entity's Transform
// (position, rotation, uniform scale), with per-instance parameters that gameplay and weather drive.
//
//   "Cloudscape": {"asset": "cloudscape.json",           // a recipe (baked on first use into the bake
//                                                         // cache) or a folder of .nvdf files written by
//                                                         // `cumulo bake` / `cumulo import`; relative to
//                                                         // the level file, or absolute
//                  "density": 1.0,                        // density multiplier (>= 0)
//                  "wind": {"direction": [1, 0, 0], "speed": 0},   // noise scroll, m/s
//                  "dissipation": 0.0,                    // 0..1: removes low-profile, wispy regions first
//                  "rain": 0.0}                           // 0..1: rain falls under the cloud (a column below
//                                                         // its box's centre, fading with dissipation)
//
// Several entities may name the same asset: they share one GPU copy. An entity whose cloud grows during play
// (gameplay::CloudGrowth, issue 26) may leave "asset" out: the renderer draws its simulation's images.
#include <filesystem>
#include <string>

#include <glm/glm.hpp>

#include "engine/core/json.h"
#include "engine/ecs/serialize.h"

namespace cumulo::clouds {

struct Cloudscape {
  std::string asset;  // as written in the level; empty only on a cloud grown during play (a CloudGrowth's entity)
  float density = 1.0f;
  glm::vec3 wind_direction{1.0f, 0.0f, 0.0f};
  float wind_speed = 0.0f;
  float dissipation = 0.0f;
  float rain = 0.0f;
  // Filled when the level loads (clouds module): the folder of NVDFs the renderer loads.
  std::filesystem::path resolved;
  std::string where;  // "level.json: $.entities[3].components.Cloudscape.asset", for later messages
};

Cloudscape cloudscape_from_json(const JsonView& v);
Json cloudscape_to_json(const Cloudscape& c);
void register_cloudscape_component(ecs::ComponentRegistry& registry);

}  // namespace cumulo::clouds
