#pragma once
// Levels: content/levels/<name>/level.json -> entities in an ecs::World, with their glTF models loaded.
//
//   ecs::World world;
//   auto& reg = world.set_resource<ecs::ComponentRegistry>();
//   scene::register_components(reg);            // + every module's components (clouds, ...)
//   scene::LevelInfo level = scene::load_level("content/levels/sample/level.json", world);
//   ecs::Entity cam = scene::find_camera(world, "ground");
//   world.view<const scene::Transform, const scene::ModelRef>().each(...);   // ModelRef::model is loaded
//
// Format (content/schemas/level.schema.json):
//   {"$schema": "...", "version": 1, "name": "sample", "description": "...",
//    "folders": {"weather": "../../weather"},
//    "entities": [{"name": "ground", "components": {"Transform": {...}, "Camera": {...}}}, ...]}
// "folders" names the data folders the level's modules read and write (the clouds' weather states), relative
// to the level file, so a copied level takes its data with it.
// Errors name the file and JSON path; a glTF that fails to load is reported at the ModelRef's "path" with
// the glTF error after it. A level that fails to load leaves the world as it was.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/json.h"
#include "engine/ecs/serialize.h"
#include "engine/ecs/world.h"
#include "engine/scene/model.h"

namespace cumulo::scene {

constexpr int kLevelVersion = 1;

struct LevelInfo {
  std::filesystem::path file;       // the level.json as given
  std::filesystem::path directory;  // where relative paths in it resolve
  std::string name;
  std::string description;
  std::vector<ecs::Entity> entities;  // in file order
  std::vector<std::string> cameras;   // names of the entities with a Camera, in file order
  std::map<std::string, std::shared_ptr<const Model>> models;  // by resolved path
  Bounds bounds;  // every ModelRef's model bounds placed by its Transform (world space)
  std::map<std::string, std::filesystem::path> folders;  // "folders", resolved against `directory`
};

// Uses world.resource<ecs::ComponentRegistry>() when the world has one, else a registry with the scene
// components only (register_components()).
LevelInfo load_level(const std::filesystem::path& path, ecs::World& world);
LevelInfo load_level(const std::filesystem::path& path, ecs::World& world, const ecs::ComponentRegistry& registry);

// The same from a parsed document (relative paths resolve against `directory`). With load_models false,
// ModelRef paths are resolved but no file is opened (fuzzing, tools that only need the entities).
LevelInfo load_level_document(const JsonDocument& doc, const std::filesystem::path& directory, ecs::World& world,
                              const ecs::ComponentRegistry& registry, bool load_models = true);

// Writes the world's entities in the level format (atomically: a failed save keeps the old file).
void save_level(const std::filesystem::path& path, const ecs::World& world, const ecs::ComponentRegistry& registry,
                const std::string& name, const std::string& description = "");

}  // namespace cumulo::scene
