#include "engine/ecs/world.h"

#include <atomic>

#include "engine/core/error.h"

namespace cumulo::ecs {

namespace detail {
uint32_t next_type_id() {
  static std::atomic<uint32_t> counter{0};
  return counter.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace detail

std::string to_string(Entity e) {
  if (e.is_null()) return "null entity";
  return strf("entity %uv%u", e.index, e.generation);
}

namespace {
std::string handle(Entity e) { return to_string(e); }
std::string type_str(std::string_view t) { return std::string(t); }
}  // namespace

// ---------------------------------------------------------------- Commands

Entity Commands::create() {
  Entity e = world_.reserve();
  struct CreateOp final : Op {
    explicit CreateOp(Entity e) : e(e) {}
    void apply(World& w) override { w.activate(e); }
    Entity e;
  };
  ops_.push_back(std::make_unique<CreateOp>(e));
  return e;
}

void Commands::destroy(Entity e) {
  check_target(e, "defer().destroy", "");
  struct DestroyOp final : Op {
    explicit DestroyOp(Entity e) : e(e) {}
    void apply(World& w) override {
      if (w.valid(e)) w.destroy(e);
    }
    Entity e;
  };
  ops_.push_back(std::make_unique<DestroyOp>(e));
}

// A handle must be alive or reserved by defer().create() when queued; whether it is still alive when the
// queue is applied is checked then (see the rules in world.h).
void Commands::check_target(Entity e, const char* what, std::string_view type) const {
  if (!world_.valid(e) && !world_.reserved(e)) world_.fail_stale(e, what, type);
}

// ---------------------------------------------------------------- World

World::World() : commands_(*this) {}
World::~World() = default;

uint32_t World::allocate_slot() {
  if (!free_.empty()) {
    uint32_t i = free_.back();
    free_.pop_back();
    return i;
  }
  if (slots_.size() >= Entity::kNullIndex) fail("ecs: out of entity slots");
  slots_.emplace_back();
  return uint32_t(slots_.size() - 1);
}

Entity World::create() {
  uint32_t i = allocate_slot();
  slots_[i].alive = true;
  ++alive_count_;
  return Entity{i, slots_[i].generation};
}

Entity World::reserve() {
  uint32_t i = allocate_slot();
  slots_[i].reserved = true;
  return Entity{i, slots_[i].generation};
}

bool World::reserved(Entity e) const {
  return e.index < slots_.size() && slots_[e.index].generation == e.generation && slots_[e.index].reserved;
}

void World::activate(Entity e) {
  if (!reserved(e)) return;  // clear() released it
  slots_[e.index].reserved = false;
  slots_[e.index].alive = true;
  ++alive_count_;
}

void World::release_reserved(Entity e) {
  if (!reserved(e)) return;
  Slot& s = slots_[e.index];
  s.reserved = false;
  ++s.generation;
  if (s.generation == 0) s.generation = 1;  // wrapped: 0 is never a live generation
  free_.push_back(e.index);
}

void World::destroy(Entity e) {
  check_valid(e, "destroy", "");
  check_unlocked(e, "destroy", "");
  for (auto& pool : pools_)
    if (pool) pool->remove(e.index);
  Slot& s = slots_[e.index];
  s.alive = false;
  ++s.generation;
  if (s.generation == 0) s.generation = 1;
  --alive_count_;
  free_.push_back(e.index);
}

void World::clear() {
  if (iteration_depth_ > 0) fail("ecs: World::clear() while a view is iterating");
  commands_.ops_.clear();
  for (uint32_t i = 0; i < slots_.size(); ++i) {
    if (slots_[i].alive)
      destroy(Entity{i, slots_[i].generation});
    else if (slots_[i].reserved)
      release_reserved(Entity{i, slots_[i].generation});
  }
}

void World::flush() {
  if (iteration_depth_ > 0) fail("ecs: World::flush() while a view is iterating; commands are applied when it ends");
  // Ops applied here may not queue more ops into this vector (they run unlocked), but take it anyway so
  // that an exception leaves the remaining ops dropped rather than half-applied twice.
  std::vector<std::unique_ptr<Commands::Op>> ops;
  ops.swap(commands_.ops_);
  for (auto& op : ops) op->apply(*this);
}

void World::end_iteration(bool apply_commands) {
  --iteration_depth_;
  if (iteration_depth_ == 0 && apply_commands) flush();
}

Entity World::find(std::string_view name) const {
  auto* pool = find_pool<Name>();
  if (!pool) return Entity::null();
  const auto& entities = pool->entities();
  for (size_t i = 0; i < entities.size(); ++i)
    if (pool->find(entities[i].index)->value == name) return entities[i];
  return Entity::null();
}

Entity World::find_or_fail(std::string_view name) const {
  Entity e = find(name);
  if (e.is_null()) fail("ecs: no entity named \"%.*s\"", int(name.size()), name.data());
  return e;
}

void World::update_events() {
  for (auto& q : events_)
    if (q) q->update();
}

void World::fail_stale(Entity e, const char* op, std::string_view type) const {
  std::string what = type.empty() ? std::string(op) : strf("%s<%s>", op, type_str(type).c_str());
  if (e.is_null()) fail("ecs: %s: null entity handle", what.c_str());
  if (e.index >= slots_.size()) fail("ecs: %s: %s was never created by this world", what.c_str(), handle(e).c_str());
  const Slot& s = slots_[e.index];
  if (s.generation == e.generation && s.reserved)
    fail("ecs: %s: %s is reserved by defer().create() and comes alive when the commands are applied", what.c_str(),
         handle(e).c_str());
  fail("ecs: %s: stale handle %s (destroyed; slot %u is now at generation %u)", what.c_str(), handle(e).c_str(),
       e.index, s.generation);
}

void World::fail_locked(Entity e, const char* op, std::string_view type) const {
  std::string what = type.empty() ? std::string(op) : strf("%s<%s>", op, type_str(type).c_str());
  fail("ecs: %s on %s while a view is iterating: structural changes must be queued with world.defer()", what.c_str(),
       handle(e).c_str());
}

void World::fail_missing(Entity e, std::string_view type) const {
  fail("ecs: get<%s>: %s has no %s component", type_str(type).c_str(), handle(e).c_str(), type_str(type).c_str());
}

void World::fail_has(Entity e, std::string_view type) const {
  fail("ecs: emplace<%s>: %s already has a %s component (use emplace_or_replace)", type_str(type).c_str(),
       handle(e).c_str(), type_str(type).c_str());
}

void World::fail_no_resource(std::string_view type) const {
  fail("ecs: resource<%s>: no such resource (set it with set_resource<%s>())", type_str(type).c_str(),
       type_str(type).c_str());
}

}  // namespace cumulo::ecs
