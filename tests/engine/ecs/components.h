#pragma once
// Plain-struct components shared by the ECS tests.
#include <string>

namespace cumulo::ecs::test {

struct Position {
  float x = 0, y = 0, z = 0;
  bool operator==(const Position&) const = default;
};
struct Velocity {
  float x = 0, y = 0, z = 0;
  bool operator==(const Velocity&) const = default;
};
struct Health {
  int hp = 100;
  bool operator==(const Health&) const = default;
};
struct Tag {};
// Counts live instances, to check that destroy/remove/clear really destroy components.
struct Tracked {
  static inline int live = 0;
  std::string label;
  Tracked(std::string l = "") : label(std::move(l)) { ++live; }
  Tracked(const Tracked& o) : label(o.label) { ++live; }
  Tracked(Tracked&& o) noexcept : label(std::move(o.label)) { ++live; }
  Tracked& operator=(const Tracked&) = default;
  Tracked& operator=(Tracked&&) = default;
  ~Tracked() { --live; }
};

}  // namespace cumulo::ecs::test
