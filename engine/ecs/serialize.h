#pragma once
// JSON (de)serialization of registered component types. This is the one place where components get
// names; every module registers its own (flecs-style: one registration function per module).
//
//   // modules/clouds/clouds_components.cpp
//   void register_cloud_components(ecs::ComponentRegistry& reg) {
//     reg.register_component<TimeOfDay>("TimeOfDay",
//         [](const TimeOfDay& t) { return Json{{"hours", t.hours}}; },
//         [](const JsonView& v) { return TimeOfDay{v["hours"].as_float_in(0.0f, 24.0f)}; });
//   }
//
//   // loading a level: errors name the file and JSON path ("level.json: $.entities[2].components.Foo: ...")
//   ecs::ComponentRegistry& reg = world.set_resource<ecs::ComponentRegistry>();
//   register_cloud_components(reg);
//   std::vector<ecs::Entity> made = ecs::load_entities(doc.view()["entities"], world);
//   Json saved = ecs::serialize_world(world);   // the same format, loadable again
//
// Format: an array of entities, each {"name": "ground", "components": {"Transform": {...}, ...}}; both keys
// are optional; "name" becomes the ecs::Name component. load_entities parses everything before creating
// anything, so a bad file leaves the world unchanged. Unknown component names, unknown keys and duplicate
// entity names are errors naming the JSON path. serialize_world writes every live entity in slot order and
// skips components that are not registered (runtime-only state).
// from_json receives the component's JsonView, so errors inside it already name file and path.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/json.h"
#include "engine/ecs/world.h"

namespace cumulo::ecs {

class ComponentRegistry {
 public:
  template <typename T>
  using ToJson = std::function<Json(const T&)>;
  template <typename T>
  using FromJson = std::function<T(const JsonView&)>;
  // Validates the JSON now and returns the action that adds the parsed component later.
  using Applier = std::function<void(World&, Entity)>;

  // Type-erased access to one registered component type (also what an editor panel needs).
  struct Entry {
    std::string name;
    uint32_t type_id = 0;
    std::function<bool(const World&, Entity)> has;
    std::function<Json(const World&, Entity)> save;  // entity must have it
    std::function<Applier(const JsonView&)> parse;   // throws cumulo::Error naming the path
    std::function<bool(World&, Entity)> remove;
    void load(World& world, Entity e, const JsonView& v) const { parse(v)(world, e); }  // emplace or replace
  };

  template <typename T>
  void register_component(std::string name, ToJson<T> to_json, FromJson<T> from_json) {
    check_new(name, detail::type_id<T>());
    Entry entry;
    entry.name = name;
    entry.type_id = detail::type_id<T>();
    entry.has = [](const World& w, Entity e) { return w.has<T>(e); };
    entry.save = [to_json](const World& w, Entity e) { return to_json(w.get<T>(e)); };
    entry.parse = [from_json, name](const JsonView& v) -> Applier {
      auto value = std::make_shared<T>(call_from_json(from_json, v, name));
      return [value](World& w, Entity e) { w.emplace_or_replace<T>(e, std::move(*value)); };
    };
    entry.remove = [](World& w, Entity e) { return w.remove<T>(e); };
    entries_.push_back(std::move(entry));
  }

  const Entry* find(std::string_view name) const;
  template <typename T>
  const Entry* find() const {
    return find_type(detail::type_id<T>());
  }
  const std::vector<Entry>& entries() const { return entries_; }  // in registration order
  std::string names() const;                                      // "Camera, Transform, ..." for messages

 private:
  void check_new(const std::string& name, uint32_t type_id) const;
  const Entry* find_type(uint32_t type_id) const;
  template <typename T>
  static T call_from_json(const FromJson<T>& from_json, const JsonView& v, const std::string& name) {
    try {
      return from_json(v);
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {  // e.g. a nlohmann type error from raw(): still name the place
      v.fail(name + ": " + e.what());
    }
  }

  std::vector<Entry> entries_;
};

// One entity as {"name": ..., "components": {...}}.
Json serialize_entity(const World& world, const ComponentRegistry& registry, Entity e);
// Every live entity, in slot order.
Json serialize_world(const World& world, const ComponentRegistry& registry);
Json serialize_world(const World& world);  // uses world.resource<ComponentRegistry>()

// Creates the entities described by `array` and returns them in array order.
std::vector<Entity> load_entities(const JsonView& array, World& world, const ComponentRegistry& registry);
std::vector<Entity> load_entities(const JsonView& array, World& world);  // uses world.resource<ComponentRegistry>()

}  // namespace cumulo::ecs
