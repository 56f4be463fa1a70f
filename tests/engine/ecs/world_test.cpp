// Entities, generations, component storage, names and resources.
#include <gtest/gtest.h>

#include <set>

#include "engine/ecs/ecs.h"  // also checks that the umbrella header compiles alone
#include "tests/engine/ecs/components.h"
#include "tests/engine/ecs/expect_error.h"

namespace cumulo::ecs {
namespace {
using namespace test;

TEST(World, CreateGivesDistinctValidHandles) {
  World w;
  std::set<Entity> seen;
  for (int i = 0; i < 100; ++i) {
    Entity e = w.create();
    EXPECT_TRUE(w.valid(e));
    EXPECT_FALSE(e.is_null());
    EXPECT_TRUE(seen.insert(e).second);
  }
  EXPECT_EQ(w.alive_count(), 100u);
  EXPECT_FALSE(w.valid(Entity::null()));
  EXPECT_FALSE(w.valid(Entity{}));
  EXPECT_FALSE(w.valid(Entity{0, 0}));  // generation 0 is never live
}

TEST(World, DestroyedHandleIsStaleEvenWhenSlotIsReused) {
  World w;
  Entity a = w.create();
  w.emplace<Health>(a, 5);
  w.destroy(a);
  EXPECT_FALSE(w.valid(a));
  Entity b = w.create();
  EXPECT_EQ(b.index, a.index);            // slot reused...
  EXPECT_NE(b.generation, a.generation);  // ...under a new generation
  EXPECT_TRUE(w.valid(b));
  EXPECT_FALSE(w.valid(a));
  EXPECT_FALSE(w.has<Health>(b));  // the old component did not leak into the new entity
  EXPECT_EQ(w.try_get<Health>(a), nullptr);
  EXPECT_FALSE(w.has<Health>(a));
  EXPECT_ERROR_HAS(w.get<Health>(a), "stale handle");
  EXPECT_ERROR_HAS(w.emplace<Health>(a, 1), "stale handle");
  EXPECT_ERROR_HAS(w.remove<Health>(a), "stale handle");
  EXPECT_ERROR_HAS(w.destroy(a), "stale handle");
  EXPECT_ERROR_HAS(w.get<Health>(Entity::null()), "null entity");
  EXPECT_ERROR_HAS(w.get<Health>(Entity{12345, 1}), "never created");
}

TEST(World, EmplaceGetTryGetHasRemove) {
  World w;
  Entity e = w.create();
  Position& p = w.emplace<Position>(e, 1.0f, 2.0f, 3.0f);
  EXPECT_EQ(p, (Position{1, 2, 3}));
  EXPECT_TRUE(w.has<Position>(e));
  EXPECT_FALSE(w.has<Velocity>(e));
  EXPECT_EQ(w.try_get<Velocity>(e), nullptr);
  w.get<Position>(e).y = 7;
  EXPECT_EQ(w.try_get<Position>(e)->y, 7);
  EXPECT_ERROR_HAS(w.emplace<Position>(e), "already has");
  EXPECT_ERROR_HAS(w.get<Velocity>(e), "has no");
  EXPECT_ERROR_HAS(w.get<Velocity>(e), "Velocity");  // names the type
  w.emplace_or_replace<Position>(e, 9.0f);
  EXPECT_EQ(w.get<Position>(e), (Position{9, 0, 0}));
  EXPECT_TRUE(w.remove<Position>(e));
  EXPECT_FALSE(w.remove<Position>(e));
  EXPECT_FALSE(w.has<Position>(e));
  EXPECT_TRUE(w.valid(e));  // removing the last component keeps the entity
  w.emplace<Tag>(e);
  EXPECT_TRUE(w.has<Tag>(e));
  const World& cw = w;
  EXPECT_NE(cw.try_get<Tag>(e), nullptr);
}

TEST(World, ComponentsStayWithTheirEntityAcrossSwapRemoval) {
  World w;
  std::vector<Entity> es;
  for (int i = 0; i < 1000; ++i) {
    es.push_back(w.create());
    w.emplace<Health>(es.back(), i);
  }
  for (int i = 0; i < 1000; i += 3) w.destroy(es[i]);
  for (int i = 1; i < 1000; i += 3) w.remove<Health>(es[i]);
  for (int i = 0; i < 1000; ++i) {
    if (i % 3 == 2)
      EXPECT_EQ(w.get<Health>(es[i]).hp, i);
    else
      EXPECT_FALSE(w.has<Health>(es[i]));
  }
  EXPECT_EQ(w.count<Health>(), 333u);
}

TEST(World, HighEntityIndicesUsePagedSparseArrays) {
  World w;
  std::vector<Entity> es;
  for (int i = 0; i < 20000; ++i) es.push_back(w.create());
  w.emplace<Health>(es.back(), 42);  // index 19999: sparse page 4
  EXPECT_EQ(w.get<Health>(es.back()).hp, 42);
  EXPECT_FALSE(w.has<Health>(es[5000]));
}

TEST(World, DestroyAndClearReleaseComponents) {
  Tracked::live = 0;
  {
    World w;
    Entity a = w.create(), b = w.create();
    w.emplace<Tracked>(a, "a");
    w.emplace<Tracked>(b, "b");
    EXPECT_EQ(Tracked::live, 2);
    w.destroy(a);
    EXPECT_EQ(Tracked::live, 1);
    EXPECT_EQ(w.get<Tracked>(b).label, "b");
    w.clear();
    EXPECT_EQ(Tracked::live, 0);
    EXPECT_EQ(w.alive_count(), 0u);
    EXPECT_FALSE(w.valid(b));
    w.emplace<Tracked>(w.create(), "c");
  }
  EXPECT_EQ(Tracked::live, 0);  // the world's destructor destroys remaining components
}

TEST(World, EachEntityVisitsLiveEntitiesInSlotOrder) {
  World w;
  Entity a = w.create(), b = w.create(), c = w.create();
  w.destroy(b);
  std::vector<Entity> seen;
  w.each_entity([&](Entity e) { seen.push_back(e); });
  EXPECT_EQ(seen, (std::vector<Entity>{a, c}));
}

TEST(World, NamesFindEntities) {
  World w;
  Entity ground = w.create();
  w.emplace<Name>(ground, "ground");
  Entity sky = w.create();
  w.emplace<Name>(sky, "immersed");
  EXPECT_EQ(w.find("ground"), ground);
  EXPECT_EQ(w.find("immersed"), sky);
  EXPECT_TRUE(w.find("mixed").is_null());
  EXPECT_ERROR_HAS(w.find_or_fail("mixed"), "no entity named \"mixed\"");
  w.destroy(ground);
  EXPECT_TRUE(w.find("ground").is_null());
}

struct TimeOfDay {
  float hours = 12.0f;
};

TEST(World, Resources) {
  World w;
  EXPECT_FALSE(w.has_resource<TimeOfDay>());
  EXPECT_EQ(w.try_resource<TimeOfDay>(), nullptr);
  EXPECT_ERROR_HAS(w.resource<TimeOfDay>(), "TimeOfDay");
  w.set_resource<TimeOfDay>(TimeOfDay{6.5f});
  EXPECT_FLOAT_EQ(w.resource<TimeOfDay>().hours, 6.5f);
  w.resource<TimeOfDay>().hours = 18.0f;
  const World& cw = w;
  EXPECT_FLOAT_EQ(cw.resource<TimeOfDay>().hours, 18.0f);
  w.set_resource<TimeOfDay>();  // replaces
  EXPECT_FLOAT_EQ(w.resource<TimeOfDay>().hours, 12.0f);
  w.remove_resource<TimeOfDay>();
  EXPECT_FALSE(w.has_resource<TimeOfDay>());
}

TEST(World, EntityToString) {
  EXPECT_EQ(to_string(Entity{3, 2}), "entity 3v2");
  EXPECT_EQ(to_string(Entity::null()), "null entity");
}

TEST(World, TypeNamesAreReadable) {
  EXPECT_EQ(detail::type_name<Position>(), "cumulo::ecs::test::Position");
  EXPECT_NE(detail::type_id<Position>(), detail::type_id<Velocity>());
  EXPECT_EQ(detail::type_id<Position>(), detail::type_id<Position>());
}

}  // namespace
}  // namespace cumulo::ecs
