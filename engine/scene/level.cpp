#include "engine/scene/level.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/scene/components.h"
#include "engine/scene/gltf.h"
#include "engine/scene/serialization.h"

namespace cumulo::scene {

namespace {

std::filesystem::path resolve(const std::filesystem::path& dir, const std::string& rel) {
  std::filesystem::path p(rel);
  return (p.is_absolute() ? p : dir / p).lexically_normal();
}

void load_models(const JsonView& entities, const std::vector<ecs::Entity>& made, ecs::World& world, LevelInfo& info) {
  for (size_t k = 0; k < made.size(); ++k) {
    ModelRef* ref = world.try_get<ModelRef>(made[k]);
    if (!ref) continue;
    JsonView where = entities.at(k)["components"]["ModelRef"]["path"];
    ref->resolved = resolve(info.directory, ref->path);
    std::string key = ref->resolved.string();
    auto it = info.models.find(key);
    if (it == info.models.end()) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(ref->resolved, ec))
        where.fail("model file not found: " + key);
      try {
        it = info.models.emplace(key, std::make_shared<const Model>(load_gltf(ref->resolved))).first;
      } catch (const Error& e) {
        where.fail(e.what());
      }
    }
    ref->model = it->second;
    glm::mat4 m = world.has<Transform>(made[k]) ? world.get<Transform>(made[k]).matrix() : glm::mat4(1.0f);
    info.bounds.add(ref->model->bounds.transformed(m));
  }
}

}  // namespace

LevelInfo load_level_document(const JsonDocument& doc, const std::filesystem::path& directory, ecs::World& world,
                              const ecs::ComponentRegistry& registry, bool with_models) {
  JsonView root = doc.view();
  check_keys(root, {"$schema", "version", "name", "description", "folders", "entities"});
  JsonView version = root["version"];
  if (version.as<int>() != kLevelVersion)
    version.fail(strf("unsupported level version %d (this build reads version %d)", version.as<int>(), kLevelVersion));

  LevelInfo info;
  info.file = doc.file();
  info.directory = directory.empty() ? std::filesystem::path(".") : directory;
  info.name = root.get<std::string>("name", std::filesystem::absolute(info.directory).lexically_normal().filename().string());
  info.description = root.get<std::string>("description", "");
  if (root.has("folders")) {
    JsonView folders = root["folders"];
    if (!folders.is_object()) folders.fail("expected an object of folder paths, e.g. {\"weather\": \"weather\"}");
    for (const std::string& kind : folders.keys()) {
      JsonView v = folders[kind];
      const std::string text = v.as<std::string>();
      if (text.empty()) v.fail("an empty folder path");
      const std::filesystem::path p(text);
      info.folders[kind] = (p.is_absolute() ? p : info.directory / p).lexically_normal();
    }
  }
  JsonView entities = root["entities"];
  info.entities = ecs::load_entities(entities, world, registry);  // parses everything before creating
  try {
    // A camera is placed by its Transform; without one `--camera NAME` could only say "no camera
    // named NAME" about a camera the level does have.
    for (size_t k = 0; k < info.entities.size(); ++k)
      if (world.has<Camera>(info.entities[k]) && !world.has<Transform>(info.entities[k]))
        entities.at(k)["components"]["Camera"].fail("a camera needs a Transform component on the same entity");
    if (with_models) {
      load_models(entities, info.entities, world, info);
    } else {
      for (ecs::Entity e : info.entities)
        if (ModelRef* ref = world.try_get<ModelRef>(e)) ref->resolved = resolve(info.directory, ref->path);
    }
  } catch (...) {
    for (ecs::Entity e : info.entities)  // leave the world as it was
      if (world.valid(e)) world.destroy(e);
    throw;
  }
  for (ecs::Entity e : info.entities)
    if (world.has<Camera>(e)) {
      const auto* n = world.try_get<ecs::Name>(e);
      info.cameras.push_back(n ? n->value : std::string());
    }
  return info;
}

LevelInfo load_level(const std::filesystem::path& path, ecs::World& world, const ecs::ComponentRegistry& registry) {
  JsonDocument doc = load_json_file(path);  // "FILE: cannot open" / "FILE:LINE:COL: JSON syntax error"
  LevelInfo info = load_level_document(doc, path.parent_path(), world, registry);
  info.file = path;
  LOG_INFO("level %s: %zu entities, %zu models, %zu cameras", path.string().c_str(), info.entities.size(),
           info.models.size(), info.cameras.size());
  return info;
}

LevelInfo load_level(const std::filesystem::path& path, ecs::World& world) {
  if (const auto* reg = world.try_resource<ecs::ComponentRegistry>()) return load_level(path, world, *reg);
  ecs::ComponentRegistry reg;
  register_components(reg);
  return load_level(path, world, reg);
}

void save_level(const std::filesystem::path& path, const ecs::World& world, const ecs::ComponentRegistry& registry,
                const std::string& name, const std::string& description) {
  Json doc = Json::object();
  doc["$schema"] = "../../schemas/level.schema.json";
  doc["version"] = kLevelVersion;
  doc["name"] = name;
  if (!description.empty()) doc["description"] = description;
  doc["entities"] = ecs::serialize_world(world, registry);
  write_file_atomic(path, doc.dump(2) + "\n");
}

}  // namespace cumulo::scene
