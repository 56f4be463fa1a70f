// Views over several components, const access, the iteration lock and deferred commands.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <type_traits>

#include "engine/ecs/world.h"
#include "tests/engine/ecs/components.h"
#include "tests/engine/ecs/expect_error.h"

namespace cumulo::ecs {
namespace {
using namespace test;

TEST(View, VisitsExactlyTheEntitiesWithAllComponents) {
  World w;
  std::map<Entity, int> expected;
  for (int i = 0; i < 300; ++i) {
    Entity e = w.create();
    if (i % 2 == 0) w.emplace<Position>(e, float(i));
    if (i % 3 == 0) w.emplace<Velocity>(e, 1.0f);
    if (i % 2 == 0 && i % 3 == 0) expected[e] = i;
  }
  std::map<Entity, int> seen;
  w.view<const Position, const Velocity>().each([&](Entity e, const Position& p, const Velocity& v) {
    EXPECT_FLOAT_EQ(v.x, 1.0f);
    seen[e] = int(p.x);
  });
  EXPECT_EQ(seen, expected);
  EXPECT_EQ(w.view<Position>().size_hint(), 150u);
  EXPECT_EQ((w.view<Position, Velocity>().size_hint()), 100u);  // the smallest pool
}

TEST(View, WritesThroughNonConstComponents) {
  World w;
  for (int i = 0; i < 10; ++i) {
    Entity e = w.create();
    w.emplace<Position>(e);
    w.emplace<Velocity>(e, float(i), 0.0f, 0.0f);
  }
  w.view<const Velocity, Position>().each([](const Velocity& v, Position& p) { p.x += v.x * 2; });
  float sum = 0;
  w.view<const Position>().each([&](const Position& p) { sum += p.x; });
  EXPECT_FLOAT_EQ(sum, 90.0f);
}

TEST(View, ConstInTheTypeListMeansConstReference) {
  World w;
  Entity e = w.create();
  w.emplace<Position>(e);
  w.emplace<Velocity>(e);
  bool called = false;
  w.view<const Position, Velocity>().each([&](auto& p, auto& v) {
    static_assert(std::is_const_v<std::remove_reference_t<decltype(p)>>);
    static_assert(!std::is_const_v<std::remove_reference_t<decltype(v)>>);
    called = true;
  });
  EXPECT_TRUE(called);
  const World& cw = w;
  int n = 0;
  cw.view<const Position>().each([&](Entity, const Position&) { ++n; });  // read-only view of a const World
  EXPECT_EQ(n, 1);
}

TEST(View, IteratesTheSmallestPool) {
  World w;
  std::vector<Entity> order;
  for (int i = 0; i < 1000; ++i) w.emplace<Position>(w.create());
  std::vector<Entity> few;
  for (int i = 0; i < 5; ++i) {
    Entity e = w.create();
    w.emplace<Position>(e);
    w.emplace<Velocity>(e);
    few.push_back(e);
  }
  // With the Velocity pool leading, the visit order is Velocity's dense order (insertion order here),
  // and the callback count equals the small pool's size, whichever order the types are listed in.
  w.view<Position, Velocity>().each([&](Entity e, Position&, Velocity&) { order.push_back(e); });
  EXPECT_EQ(order, few);
  order.clear();
  w.view<Velocity, Position>().each([&](Entity e, Velocity&, Position&) { order.push_back(e); });
  EXPECT_EQ(order, few);
}

TEST(View, ExcludeSkipsEntitiesWithThoseComponents) {
  World w;
  std::vector<Entity> es;
  for (int i = 0; i < 12; ++i) {
    Entity e = w.create();
    w.emplace<Health>(e, i);
    if (i % 3 == 0) w.emplace<Tag>(e);
    if (i % 4 == 0) w.emplace<Velocity>(e);
    es.push_back(e);
  }
  std::vector<int> seen;
  w.view<const Health>(exclude<Tag>).each([&](const Health& h) { seen.push_back(h.hp); });
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 4, 5, 7, 8, 10, 11}));
  seen.clear();
  w.view<const Health>(exclude<Tag, Velocity>).each([&](const Health& h) { seen.push_back(h.hp); });
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 5, 7, 10, 11}));
  seen.clear();
  w.view<const Health>(exclude<Position>).each([&](const Health& h) { seen.push_back(h.hp); });  // no such pool
  EXPECT_EQ(seen.size(), 12u);
  EXPECT_FALSE(w.view<const Health>(exclude<Tag>).contains(es[3]));
  EXPECT_TRUE(w.view<const Health>(exclude<Tag>).contains(es[4]));
  const World& cw = w;
  int n = 0;
  cw.view<const Health>(exclude<Velocity>).each([&](Entity, const Health&) { ++n; });
  EXPECT_EQ(n, 9);
}

TEST(View, MissingPoolMeansEmptyView) {
  World w;
  w.emplace<Position>(w.create());
  int n = 0;
  w.view<Position, Health>().each([&](Position&, Health&) { ++n; });
  EXPECT_EQ(n, 0);
  EXPECT_EQ((w.view<Position, Health>().size_hint()), 0u);
}

TEST(View, ContainsChecksAllComponentsAndValidity) {
  World w;
  Entity a = w.create(), b = w.create();
  w.emplace<Position>(a);
  w.emplace<Velocity>(a);
  w.emplace<Position>(b);
  auto v = w.view<const Position, const Velocity>();
  EXPECT_TRUE(v.contains(a));
  EXPECT_FALSE(v.contains(b));
  w.destroy(a);
  EXPECT_FALSE(v.contains(a));
}

TEST(View, StructuralChangesWhileIteratingThrowAndLeaveTheWorldIntact) {
  World w;
  Entity a = w.create();
  w.emplace<Position>(a);
  w.view<Position>().each([&](Entity e, Position&) {
    EXPECT_TRUE(w.iterating());
    EXPECT_ERROR_HAS(w.emplace<Velocity>(e), "world.defer()");
    EXPECT_ERROR_HAS(w.remove<Position>(e), "while a view is iterating");
    EXPECT_ERROR_HAS(w.destroy(e), "while a view is iterating");
    EXPECT_ERROR_HAS(w.emplace_or_replace<Velocity>(e), "while a view is iterating");
    EXPECT_ERROR_HAS(w.flush(), "while a view is iterating");
    EXPECT_ERROR_HAS(w.clear(), "while a view is iterating");
    w.emplace_or_replace<Position>(e, 5.0f);  // replacing a value is not structural
    Entity made = w.create();                 // neither is creating an entity with no components
    EXPECT_TRUE(w.valid(made));
  });
  EXPECT_FALSE(w.iterating());
  EXPECT_EQ(w.get<Position>(a).x, 5.0f);
  EXPECT_EQ(w.alive_count(), 2u);
}

TEST(View, DeferredChangesApplyAfterTheOutermostEach) {
  World w;
  std::vector<Entity> es;
  for (int i = 0; i < 100; ++i) {
    Entity e = w.create();
    w.emplace<Health>(e, i);
    es.push_back(e);
  }
  int visited = 0;
  Entity spawned;
  w.view<Health>().each([&](Entity e, Health& h) {
    ++visited;
    if (h.hp % 2 == 0)
      w.defer().destroy(e);
    else
      w.defer().emplace<Velocity>(e, float(h.hp));
    if (h.hp == 7) {
      spawned = w.defer().create();
      w.defer().emplace<Health>(spawned, 1000);
      EXPECT_FALSE(w.valid(spawned));  // comes alive when the commands are applied
      EXPECT_ERROR_HAS(w.get<Health>(spawned), "reserved by defer().create()");
    }
    // A nested view does not apply the queue when it ends: only the outermost one does.
    w.view<const Health>().each([&](const Health&) {});
    EXPECT_TRUE(w.valid(e));
  });
  EXPECT_EQ(visited, 100);  // the entity spawned during iteration is not visited
  EXPECT_TRUE(w.defer().empty());
  EXPECT_TRUE(w.valid(spawned));
  EXPECT_EQ(w.get<Health>(spawned).hp, 1000);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(w.valid(es[i]), i % 2 == 1);
    if (i % 2) EXPECT_EQ(w.get<Velocity>(es[i]).x, float(i));
  }
  EXPECT_EQ(w.alive_count(), 51u);
}

TEST(View, DeferredRemoveAndOpsOnEntitiesDeadAtApplyTime) {
  World w;
  Entity a = w.create(), b = w.create();
  w.emplace<Position>(a);
  w.emplace<Position>(b);
  w.emplace<Velocity>(b);
  w.view<Position>().each([&](Entity e, Position&) {
    if (e == b) {
      w.defer().remove<Velocity>(b);
      w.defer().destroy(a);
      w.defer().destroy(a);             // a second system destroying the same entity is harmless
      w.defer().emplace<Health>(a, 3);  // a is dead when this applies: skipped
    }
  });
  EXPECT_FALSE(w.valid(a));
  EXPECT_FALSE(w.has<Velocity>(b));
  EXPECT_EQ(w.count<Health>(), 0u);
  // A handle that is already stale when queued is an error right away.
  EXPECT_ERROR_HAS(w.defer().destroy(a), "stale handle");
  EXPECT_ERROR_HAS(w.defer().emplace<Health>(a, 1), "defer().emplace<cumulo::ecs::test::Health>");
}

TEST(View, DeferOutsideIterationWaitsForFlush) {
  World w;
  Entity e = w.create();
  w.defer().emplace<Health>(e, 9);
  EXPECT_FALSE(w.has<Health>(e));
  w.flush();
  EXPECT_EQ(w.get<Health>(e).hp, 9);
  w.defer().emplace<Health>(e, 10);  // deferred emplace replaces
  w.flush();
  EXPECT_EQ(w.get<Health>(e).hp, 10);
}

TEST(View, ExceptionInsideEachUnlocksWithoutApplying) {
  World w;
  Entity e = w.create();
  w.emplace<Health>(e);
  EXPECT_THROW(w.view<Health>().each([&](Entity x, Health&) {
    w.defer().destroy(x);
    throw std::runtime_error("boom");
  }),
               std::runtime_error);
  EXPECT_FALSE(w.iterating());
  EXPECT_TRUE(w.valid(e));  // still queued, applied at the next flush
  w.flush();
  EXPECT_FALSE(w.valid(e));
}

TEST(View, ClearReleasesReservedHandles) {
  World w;
  Entity r = w.defer().create();
  w.clear();
  w.flush();
  EXPECT_FALSE(w.valid(r));
  EXPECT_EQ(w.alive_count(), 0u);
  Entity n = w.create();
  EXPECT_NE(n, r);
}

}  // namespace
}  // namespace cumulo::ecs
