#pragma once
// cumulo::ecs::World: entities, components, views, deferred commands, events and resources.
//
// [Index]
//   Entities    create() destroy(e) valid(e) alive_count() each_entity(fn)
//   Components  emplace<T>(e, args...) emplace_or_replace<T> get<T> try_get<T> has<T> remove<T> count<T>
//   Views       view<const A, B>().each([](Entity e, const A& a, B& b) {...})   (Entity parameter optional)
//               view<const A>(exclude<C, D>): also skip entities that have C or D
//   Deferral    defer().create()/destroy(e)/emplace<T>(e, ...)/remove<T>(e); flush()
//   Names       Name component, find("ground")
//   Events      emit(T), events<T>(), read(EventReader<T>&), update_events()   (see events.h)
//   Resources   set_resource<T>(args...), resource<T>(), try_resource<T>(), has_resource<T>(), remove_resource<T>()
//
// Rules
// - Components are plain structs (movable). One component of each type per entity.
// - A stale handle (its entity was destroyed) is never valid(); get/emplace/remove/destroy through it throw
//   cumulo::Error naming the handle and the component type. has/try_get answer false/nullptr.
// - While any view is iterating, the world's structure is locked: emplace (of a new component), remove and
//   destroy throw. Queue them with defer() instead; the queue is applied in order when the outermost each()
//   returns (and by flush(), and by the Scheduler after every system). create() is always allowed: it touches
//   no component storage. Components may be modified in place at any time.
// - A deferred operation on an entity that is dead by the time it is applied is skipped (two systems may both
//   destroy the same entity in one step); a deferred emplace replaces an existing component.
// - Not thread-safe: one thread owns a World.
//
//   World w;
//   Entity e = w.create();
//   w.emplace<Position>(e, 1.0f, 2.0f, 3.0f);
//   w.view<const Velocity, Position>().each([&](Entity e, const Velocity& v, Position& p) {
//     p.x += v.x * dt;
//     if (p.y < 0) w.defer().destroy(e);   // applied after each() returns
//   });
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "engine/ecs/detail/pool.h"
#include "engine/ecs/detail/type_info.h"
#include "engine/ecs/entity.h"
#include "engine/ecs/events.h"

namespace cumulo::ecs {

class World;
template <typename... Ts>
class View;

// Entities that have any of these components are skipped: world.view<const Trigger>(exclude<Fired>).
template <typename... Ts>
struct Exclude {};
template <typename... Ts>
inline constexpr Exclude<Ts...> exclude{};
inline constexpr size_t kMaxExcluded = 4;

// "entity 3v2" (slot 3, generation 2) or "null entity", for logs and messages.
std::string to_string(Entity e);

// Optional entity name; levels refer to entities (cameras "ground", "mixed", "immersed") by it.
struct Name {
  std::string value;
};

// Deferred structural changes, applied in the order they were queued. Obtain it with World::defer().
class Commands {
 public:
  // A handle that becomes valid when the queue is applied (not before).
  Entity create();
  void destroy(Entity e);
  template <typename T, typename... Args>
  void emplace(Entity e, Args&&... args);
  template <typename T>
  void remove(Entity e);

  size_t size() const { return ops_.size(); }
  bool empty() const { return ops_.empty(); }

 private:
  friend class World;
  struct Op {
    virtual ~Op() = default;
    virtual void apply(World& world) = 0;
  };
  explicit Commands(World& world) : world_(world) {}
  void check_target(Entity e, const char* what, std::string_view type) const;

  World& world_;
  std::vector<std::unique_ptr<Op>> ops_;
};

class World {
 public:
  World();
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // ---- Entities
  Entity create();
  void destroy(Entity e);  // removes every component; the handle becomes stale
  bool valid(Entity e) const {
    return e.index < slots_.size() && slots_[e.index].generation == e.generation && slots_[e.index].alive;
  }
  size_t alive_count() const { return alive_count_; }
  // fn(Entity) for every live entity, in slot order (deterministic for serialization).
  template <typename F>
  void each_entity(F&& fn) const {
    for (uint32_t i = 0; i < slots_.size(); ++i)
      if (slots_[i].alive) fn(Entity{i, slots_[i].generation});
  }
  void clear();  // destroys every entity and drops pending commands; resources and events stay

  // ---- Components
  template <typename T, typename... Args>
  T& emplace(Entity e, Args&&... args) {
    check_valid(e, "emplace", detail::type_name_v<T>);
    check_unlocked(e, "emplace", detail::type_name_v<T>);
    auto& pool = pool_for<T>();
    if (pool.contains(e.index)) fail_has(e, detail::type_name_v<T>);
    return pool.emplace(e, std::forward<Args>(args)...);
  }
  template <typename T, typename... Args>
  T& emplace_or_replace(Entity e, Args&&... args) {
    check_valid(e, "emplace_or_replace", detail::type_name_v<T>);
    if (auto* pool = find_pool<T>())
      if (T* existing = pool->find(e.index)) return *existing = T(std::forward<Args>(args)...);
    check_unlocked(e, "emplace_or_replace", detail::type_name_v<T>);
    return pool_for<T>().emplace(e, std::forward<Args>(args)...);
  }
  template <typename T>
  T& get(Entity e) {
    check_valid(e, "get", detail::type_name_v<T>);
    auto* pool = find_pool<T>();
    T* c = pool ? pool->find(e.index) : nullptr;
    if (!c) fail_missing(e, detail::type_name_v<T>);
    return *c;
  }
  template <typename T>
  const T& get(Entity e) const {
    return const_cast<World*>(this)->get<T>(e);
  }
  template <typename T>
  T* try_get(Entity e) {
    auto* pool = find_pool<T>();
    return pool && valid(e) ? pool->find(e.index) : nullptr;
  }
  template <typename T>
  const T* try_get(Entity e) const {
    return const_cast<World*>(this)->try_get<T>(e);
  }
  template <typename T>
  bool has(Entity e) const {
    return try_get<T>(e) != nullptr;
  }
  // Returns whether the entity had the component.
  template <typename T>
  bool remove(Entity e) {
    check_valid(e, "remove", detail::type_name_v<T>);
    check_unlocked(e, "remove", detail::type_name_v<T>);
    auto* pool = find_pool<T>();
    return pool && pool->remove(e.index);
  }
  template <typename T>
  size_t count() const {
    auto* pool = find_pool<T>();
    return pool ? pool->size() : 0;
  }

  // ---- Views: `const` in the type list means read-only (passed as const&).
  template <typename... Ts, typename... Ex>
  View<Ts...> view(Exclude<Ex...> = {}) {
    static_assert(sizeof...(Ex) <= kMaxExcluded, "too many excluded component types");
    return View<Ts...>(this, {find_pool<Ex>()...}, find_pool<std::remove_const_t<Ts>>()...);
  }
  template <typename... Ts, typename... Ex>
  View<Ts...> view(Exclude<Ex...> ex = {}) const {
    static_assert((std::is_const_v<Ts> && ...), "a view of a const World must list only const components");
    return const_cast<World*>(this)->view<Ts...>(ex);  // only to count the iteration lock; components stay const
  }

  // ---- Deferred structural changes
  Commands& defer() { return commands_; }
  void flush();  // applies queued commands now (throws if a view is iterating)
  bool iterating() const { return iteration_depth_ > 0; }

  // ---- Names (linear scan: meant for level set-up and tools, not per-entity per-frame lookups)
  Entity find(std::string_view name) const;  // Entity::null() if none
  Entity find_or_fail(std::string_view name) const;

  // ---- Events
  template <typename T>
  void emit(T event) {
    events<T>().emit(std::move(event));
  }
  template <typename T>
  EventQueue<T>& events() {
    auto& slot = slot_for(events_, detail::type_id<T>());
    if (!slot) slot = std::make_unique<EventQueue<T>>();
    return static_cast<EventQueue<T>&>(*slot);
  }
  template <typename T>
  EventRange<T> read(EventReader<T>& reader) {
    return reader.read(events<T>());
  }
  void update_events();  // start of a simulation step: see events.h

  // ---- Resources (one value per type: TimeOfDay, the component registry, settings)
  template <typename T, typename... Args>
  T& set_resource(Args&&... args) {
    auto& slot = slot_for(resources_, detail::type_id<T>());
    slot = std::make_unique<Resource<T>>(std::forward<Args>(args)...);
    return static_cast<Resource<T>&>(*slot).value;
  }
  template <typename T>
  T* try_resource() {
    uint32_t id = detail::type_id<T>();
    return id < resources_.size() && resources_[id] ? &static_cast<Resource<T>&>(*resources_[id]).value : nullptr;
  }
  template <typename T>
  const T* try_resource() const {
    return const_cast<World*>(this)->try_resource<T>();
  }
  template <typename T>
  T& resource() {
    T* r = try_resource<T>();
    if (!r) fail_no_resource(detail::type_name_v<T>);
    return *r;
  }
  template <typename T>
  const T& resource() const {
    return const_cast<World*>(this)->resource<T>();
  }
  template <typename T>
  bool has_resource() const {
    return try_resource<T>() != nullptr;
  }
  template <typename T>
  void remove_resource() {
    uint32_t id = detail::type_id<T>();
    if (id < resources_.size()) resources_[id].reset();
  }

  // ---- Internals used by View, Commands and serialization.
  template <typename T>
  detail::Pool<T>* find_pool() const {
    uint32_t id = detail::type_id<T>();
    return id < pools_.size() ? static_cast<detail::Pool<T>*>(pools_[id].get()) : nullptr;
  }
  void begin_iteration() { ++iteration_depth_; }
  void end_iteration(bool apply_commands);
  Entity reserve();                 // a handle for Commands::create, not yet alive
  bool reserved(Entity e) const;    // reserved by Commands::create and not yet applied
  void activate(Entity e);          // makes a reserved handle alive
  void release_reserved(Entity e);  // frees a reserved handle that never came alive
  [[noreturn]] void fail_stale(Entity e, const char* op, std::string_view type) const;

 private:
  struct Slot {
    uint32_t generation = 1;
    bool alive = false;
    bool reserved = false;
  };
  struct ResourceBase {
    virtual ~ResourceBase() = default;
  };
  template <typename T>
  struct Resource final : ResourceBase {
    template <typename... Args>
    explicit Resource(Args&&... args) : value(std::forward<Args>(args)...) {}
    T value;
  };

  template <typename P>
  static std::unique_ptr<P>& slot_for(std::vector<std::unique_ptr<P>>& v, uint32_t id) {
    if (id >= v.size()) v.resize(id + 1);
    return v[id];
  }
  template <typename T>
  detail::Pool<T>& pool_for() {
    auto& slot = slot_for(pools_, detail::type_id<T>());
    if (!slot) slot = std::make_unique<detail::Pool<T>>(detail::type_name_v<T>);
    return static_cast<detail::Pool<T>&>(*slot);
  }
  uint32_t allocate_slot();
  void check_valid(Entity e, const char* op, std::string_view type) const {
    if (!valid(e)) fail_stale(e, op, type);
  }
  void check_unlocked(Entity e, const char* op, std::string_view type) const {
    if (iteration_depth_ > 0) fail_locked(e, op, type);
  }
  [[noreturn]] void fail_locked(Entity e, const char* op, std::string_view type) const;
  [[noreturn]] void fail_missing(Entity e, std::string_view type) const;
  [[noreturn]] void fail_has(Entity e, std::string_view type) const;
  [[noreturn]] void fail_no_resource(std::string_view type) const;

  std::vector<Slot> slots_;
  std::vector<uint32_t> free_;  // freed slot indices, reused LIFO (their generation was bumped)
  size_t alive_count_ = 0;
  std::vector<std::unique_ptr<detail::PoolBase>> pools_;  // indexed by detail::type_id
  std::vector<std::unique_ptr<detail::EventQueueBase>> events_;
  std::vector<std::unique_ptr<ResourceBase>> resources_;
  Commands commands_;
  int iteration_depth_ = 0;
};

// A query over entities that have every listed component. Cheap to create; holds no copies.
template <typename... Ts>
class View {
  static_assert(sizeof...(Ts) > 0, "a view needs at least one component type");

 public:
  View(World* world, std::initializer_list<const detail::PoolBase*> excluded,
       detail::Pool<std::remove_const_t<Ts>>*... pools)
      : world_(world), pools_(pools...) {
    for (const detail::PoolBase* p : excluded)
      if (p) excluded_[excluded_count_++] = p;  // an absent pool excludes nothing
  }

  // fn(Entity, C&...) or fn(C&...), C = const T for `const T` in the list. Iterates the smallest pool and
  // skips entities that lack any other component. Structural changes inside go through world.defer().
  template <typename F>
  void each(F&& fn) {
    if (!all_present(std::index_sequence_for<Ts...>{})) return;
    size_t lead = smallest(std::index_sequence_for<Ts...>{});
    world_->begin_iteration();
    try {
      dispatch(fn, lead, std::index_sequence_for<Ts...>{});
    } catch (...) {
      world_->end_iteration(false);
      throw;
    }
    world_->end_iteration(true);
  }

  // Upper bound of the number of matches (size of the smallest pool).
  size_t size_hint() const {
    if (!all_present(std::index_sequence_for<Ts...>{})) return 0;
    return min_size(std::index_sequence_for<Ts...>{});
  }
  bool contains(Entity e) const {
    return world_->valid(e) && has_all(e, std::index_sequence_for<Ts...>{}) && !excluded(e);
  }

 private:
  template <size_t I>
  using Component = std::tuple_element_t<I, std::tuple<Ts...>>;

  template <size_t... Is>
  bool all_present(std::index_sequence<Is...>) const {
    return ((std::get<Is>(pools_) != nullptr) && ...);
  }
  template <size_t... Is>
  bool has_all(Entity e, std::index_sequence<Is...>) const {
    return ((std::get<Is>(pools_) != nullptr && std::get<Is>(pools_)->contains(e.index)) && ...);
  }
  template <size_t... Is>
  size_t min_size(std::index_sequence<Is...>) const {
    size_t m = SIZE_MAX;
    ((m = std::get<Is>(pools_)->size() < m ? std::get<Is>(pools_)->size() : m), ...);
    return m;
  }
  template <size_t... Is>
  size_t smallest(std::index_sequence<Is...>) const {
    size_t best = 0, best_size = SIZE_MAX;
    ((std::get<Is>(pools_)->size() < best_size ? (best = Is, best_size = std::get<Is>(pools_)->size()) : 0), ...);
    return best;
  }
  template <typename F, size_t... Is>
  void dispatch(F& fn, size_t lead, std::index_sequence<Is...>) {
    ((lead == Is ? (run<Is>(fn, std::index_sequence<Is...>{}), true) : false) || ...);
  }

  // The lead pool's components are read by dense position; the others through their sparse arrays.
  // The structure is locked while this runs, so sizes and array pointers are loop invariants.
  template <size_t Lead, typename F, size_t... Is>
  void run(F& fn, std::index_sequence<Is...>) {
    constexpr uint32_t kAbsent = detail::PoolBase::kAbsent;
    const detail::PoolBase::Lookup lookups[] = {std::get<Is>(pools_)->lookup()...};
    const std::tuple<std::remove_const_t<Ts>*...> data{std::get<Is>(pools_)->data()...};
    const Entity* entities = std::get<Lead>(pools_)->entities().data();
    const size_t n = std::get<Lead>(pools_)->size();
    const bool any_excluded = excluded_count_ > 0;
    uint32_t pos[sizeof...(Ts)];
    for (size_t i = 0; i < n; ++i) {
      const Entity e = entities[i];
      const bool match = (((pos[Is] = (Is == Lead ? uint32_t(i) : lookups[Is].position(e.index))) != kAbsent) && ...);
      if (!match || (any_excluded && excluded(e))) continue;
      invoke(fn, e, static_cast<Component<Is>&>(std::get<Is>(data)[pos[Is]])...);
    }
  }
  bool excluded(Entity e) const {
    for (size_t k = 0; k < excluded_count_; ++k)
      if (excluded_[k]->contains(e.index)) return true;
    return false;
  }
  template <typename F, typename... Cs>
  static void invoke(F& fn, Entity e, Cs&... cs) {
    if constexpr (std::is_invocable_v<F&, Entity, Cs&...>)
      fn(e, cs...);
    else
      fn(cs...);
  }

  World* world_;
  const detail::PoolBase* excluded_[kMaxExcluded] = {};
  size_t excluded_count_ = 0;
  std::tuple<detail::Pool<std::remove_const_t<Ts>>*...> pools_;
};

// ---- Commands templates (need the complete World)

template <typename T, typename... Args>
void Commands::emplace(Entity e, Args&&... args) {
  check_target(e, "defer().emplace", detail::type_name_v<T>);
  struct EmplaceOp final : Op {
    EmplaceOp(Entity e, T v) : e(e), value(std::move(v)) {}
    void apply(World& w) override {
      if (w.valid(e)) w.emplace_or_replace<T>(e, std::move(value));
    }
    Entity e;
    T value;
  };
  ops_.push_back(std::make_unique<EmplaceOp>(e, T(std::forward<Args>(args)...)));
}

template <typename T>
void Commands::remove(Entity e) {
  check_target(e, "defer().remove", detail::type_name_v<T>);
  struct RemoveOp final : Op {
    explicit RemoveOp(Entity e) : e(e) {}
    void apply(World& w) override {
      if (w.valid(e)) w.remove<T>(e);
    }
    Entity e;
  };
  ops_.push_back(std::make_unique<RemoveOp>(e));
}

}  // namespace cumulo::ecs
