#pragma once
// ecs::Entity: a handle (slot index + generation). Destroying an entity bumps its slot's generation, so
// every old handle to it becomes stale and World::valid() reports false; accessing components through a
// stale handle throws cumulo::Error naming the handle.
#include <cstdint>
#include <functional>

namespace cumulo::ecs {

struct Entity {
  static constexpr uint32_t kNullIndex = 0xFFFFFFFFu;

  uint32_t index = kNullIndex;
  uint32_t generation = 0;  // live generations start at 1, so a zeroed handle is never valid

  static constexpr Entity null() { return Entity{}; }
  constexpr bool is_null() const { return index == kNullIndex; }
  constexpr uint64_t bits() const { return (uint64_t(generation) << 32) | index; }

  friend constexpr bool operator==(Entity a, Entity b) = default;
  friend constexpr bool operator<(Entity a, Entity b) { return a.bits() < b.bits(); }
};

}  // namespace cumulo::ecs

template <>
struct std::hash<cumulo::ecs::Entity> {
  size_t operator()(cumulo::ecs::Entity e) const noexcept { return std::hash<uint64_t>()(e.bits()); }
};
