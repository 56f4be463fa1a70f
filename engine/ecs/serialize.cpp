#include "engine/ecs/serialize.h"

#include <unordered_map>

#include "engine/core/message.h"
namespace cumulo::ecs {

void ComponentRegistry::check_new(const std::string& name, uint32_t type_id) const {
  if (name.empty()) fail("ecs: register_component: empty component name");
  if (name == "name" || name == "components") fail("ecs: register_component: \"%s\" is reserved", name.c_str());
  if (find(name)) fail("ecs: register_component: \"%s\" is already registered", name.c_str());
  if (const Entry* e = find_type(type_id))
    fail("ecs: register_component: \"%s\" is the same C++ type as the already registered \"%s\"", name.c_str(),
         e->name.c_str());
}

const ComponentRegistry::Entry* ComponentRegistry::find(std::string_view name) const {
  for (const Entry& e : entries_)
    if (e.name == name) return &e;
  return nullptr;
}

const ComponentRegistry::Entry* ComponentRegistry::find_type(uint32_t type_id) const {
  for (const Entry& e : entries_)
    if (e.type_id == type_id) return &e;
  return nullptr;
}

std::string ComponentRegistry::names() const {
  std::string out;
  for (const Entry& e : entries_) out += (out.empty() ? "" : ", ") + e.name;
  return out.empty() ? "none" : out;
}

Json serialize_entity(const World& world, const ComponentRegistry& registry, Entity e) {
  if (!world.valid(e)) world.fail_stale(e, "serialize_entity", "");
  Json out = Json::object();
  if (const Name* n = world.try_get<Name>(e)) out["name"] = n->value;
  Json components = Json::object();
  for (const auto& entry : registry.entries())
    if (entry.has(world, e)) components[entry.name] = entry.save(world, e);
  out["components"] = std::move(components);
  return out;
}

Json serialize_world(const World& world, const ComponentRegistry& registry) {
  Json out = Json::array();
  world.each_entity([&](Entity e) { out.push_back(serialize_entity(world, registry, e)); });
  return out;
}

Json serialize_world(const World& world) { return serialize_world(world, world.resource<ComponentRegistry>()); }

namespace {
struct ParsedEntity {
  std::string name;  // empty: unnamed
  std::vector<ComponentRegistry::Applier> components;
};
}  // namespace

std::vector<Entity> load_entities(const JsonView& array, World& world, const ComponentRegistry& registry) {
  if (world.iterating()) fail("ecs: load_entities while a view is iterating (%s)", array.where().c_str());
  if (!array.is_array()) array.fail("expected an array of entities");

  // Parse and check everything first, so that a bad file leaves the world untouched.
  std::vector<ParsedEntity> parsed;
  std::unordered_map<std::string, std::string> name_paths;  // name -> path where it was first used
  for (const JsonView& ev : array.elements()) {
    if (!ev.is_object()) ev.fail("expected an entity object {\"name\": ..., \"components\": {...}}");
    for (const std::string& key : ev.keys())
      if (key != "name" && key != "components")
        ev[key].fail("unknown entity key " + quote(key, 64) + " (expected \"name\" or \"components\")");
    ParsedEntity p;
    if (ev.has("name")) {
      JsonView nv = ev["name"];
      p.name = nv.as<std::string>();
      if (p.name.empty()) nv.fail("entity name must not be empty");
      auto [it, inserted] = name_paths.emplace(p.name, nv.path());
      if (!inserted) nv.fail("duplicate entity name " + quote(p.name, 64) + " (first used at " + it->second + ")");
      if (!world.find(p.name).is_null()) nv.fail("an entity named " + quote(p.name, 64) + " already exists in the world");
    }
    if (ev.has("components")) {
      JsonView cv = ev["components"];
      if (!cv.is_object()) cv.fail("expected an object mapping component names to values");
      for (const std::string& key : cv.keys()) {
        const ComponentRegistry::Entry* entry = registry.find(key);
        if (!entry) cv[key].fail("unknown component " + quote(key, 64) + " (registered: " + registry.names() + ")");
        p.components.push_back(entry->parse(cv[key]));
      }
    }
    parsed.push_back(std::move(p));
  }

  std::vector<Entity> made;
  made.reserve(parsed.size());
  for (ParsedEntity& p : parsed) {
    Entity e = world.create();
    if (!p.name.empty()) world.emplace<Name>(e, Name{std::move(p.name)});
    for (auto& apply : p.components) apply(world, e);
    made.push_back(e);
  }
  return made;
}

std::vector<Entity> load_entities(const JsonView& array, World& world) {
  return load_entities(array, world, world.resource<ComponentRegistry>());
}

}  // namespace cumulo::ecs
