// ComponentRegistry, serialize_world and load_entities.
#include "engine/ecs/serialize.h"

#include <gtest/gtest.h>

#include "tests/engine/ecs/components.h"
#include "tests/engine/ecs/expect_error.h"

namespace cumulo::ecs {
namespace {
using namespace test;

void register_test_components(ComponentRegistry& reg) {
  reg.register_component<Position>(
      "Position",
      [](const Position& p) {
        return Json::array({p.x, p.y, p.z});
      },
      [](const JsonView& v) {
        glm::vec3 p = v.as_vec3();
        return Position{p.x, p.y, p.z};
      });
  reg.register_component<Health>(
      "Health",
      [](const Health& h) {
        return Json{{"hp", h.hp}};
      },
      [](const JsonView& v) { return Health{v.get<int>("hp", 100)}; });
  reg.register_component<Tag>(
      "Tag", [](const Tag&) { return Json::object(); }, [](const JsonView&) { return Tag{}; });
}

struct Fixture : ::testing::Test {
  Fixture() { register_test_components(world.set_resource<ComponentRegistry>()); }
  std::vector<Entity> load(const std::string& text) {
    docs.push_back(parse_json_text(text, "level.json"));
    return load_entities(docs.back().view(), world);
  }
  World world;
  std::vector<JsonDocument> docs;  // keep the JSON alive while views point into it
};
using Serialize = Fixture;

TEST_F(Serialize, LoadsNamesAndComponents) {
  auto made = load(R"([
    {"name": "ground", "components": {"Position": [1, 2, 3], "Health": {"hp": 7}}},
    {"components": {"Tag": {}}},
    {"name": "immersed"}
  ])");
  ASSERT_EQ(made.size(), 3u);
  EXPECT_EQ(world.find("ground"), made[0]);
  EXPECT_EQ(world.get<Position>(made[0]), (Position{1, 2, 3}));
  EXPECT_EQ(world.get<Health>(made[0]).hp, 7);
  EXPECT_TRUE(world.has<Tag>(made[1]));
  EXPECT_FALSE(world.has<Name>(made[1]));
  EXPECT_EQ(world.find("immersed"), made[2]);
}

TEST_F(Serialize, RoundTripsThroughJson) {
  load(R"([{"name": "a", "components": {"Position": [1, 2, 3], "Health": {"hp": 3}}},
           {"components": {"Tag": {}, "Health": {}}}])");
  Entity runtime = world.create();
  world.emplace<Velocity>(runtime, 1.0f);  // not registered: not saved
  Json saved = serialize_world(world);
  ASSERT_EQ(saved.size(), 3u);
  EXPECT_EQ(saved[0]["name"], "a");
  EXPECT_EQ(saved[0]["components"]["Position"], Json::array({1.0, 2.0, 3.0}));
  EXPECT_EQ(saved[1]["components"]["Health"]["hp"], 100);
  EXPECT_FALSE(saved[1].contains("name"));
  EXPECT_TRUE(saved[2]["components"].empty());

  World other;
  ComponentRegistry reg;
  register_test_components(reg);
  JsonDocument doc(saved, "saved.json");
  load_entities(doc.view(), other, reg);
  EXPECT_EQ(serialize_world(other, reg), saved);
}

TEST_F(Serialize, UnknownComponentNamesThePath) {
  EXPECT_ERROR_HAS(
      load(R"([{"components": {"Position": [0,0,0]}}, {"components": {"Camera": {}}}])"),
      "level.json: $[1].components.Camera: unknown component \"Camera\" (registered: Position, Health, Tag)");
  EXPECT_EQ(world.alive_count(), 0u);  // nothing created: the load is all or nothing
}

TEST_F(Serialize, BadComponentValueNamesThePath) {
  EXPECT_ERROR_HAS(load(R"([{"components": {"Health": {"hp": "lots"}}}])"), "level.json: $[0].components.Health.hp:");
  EXPECT_ERROR_HAS(load(R"([{"components": {"Position": [1, 2]}}])"), "$[0].components.Position");
  EXPECT_EQ(world.alive_count(), 0u);
}

TEST_F(Serialize, StructuralErrors) {
  EXPECT_ERROR_HAS(load(R"({"name": "x"})"), "level.json: $: expected an array of entities");
  EXPECT_ERROR_HAS(load(R"([3])"), "$[0]: expected an entity object");
  EXPECT_ERROR_HAS(load(R"([{"nmae": "x"}])"), "$[0].nmae: unknown entity key \"nmae\"");
  EXPECT_ERROR_HAS(load(R"([{"components": [1]}])"), "$[0].components: expected an object");
  EXPECT_ERROR_HAS(load(R"([{"name": 5}])"), "$[0].name:");
  EXPECT_ERROR_HAS(load(R"([{"name": ""}])"), "must not be empty");
  EXPECT_ERROR_HAS(load(R"([{"name": "cam"}, {"name": "cam"}])"),
                   "$[1].name: duplicate entity name \"cam\" (first used at $[0].name)");
  load(R"([{"name": "cam"}])");
  EXPECT_ERROR_HAS(load(R"([{"name": "cam"}])"), "already exists in the world");
  EXPECT_EQ(world.alive_count(), 1u);
}

TEST_F(Serialize, ThrowingFromJsonIsWrappedWithThePath) {
  ComponentRegistry reg;
  reg.register_component<Velocity>(
      "Velocity", [](const Velocity&) { return Json(); },
      [](const JsonView& v) { return Velocity{v.raw().get<float>()}; });  // nlohmann throws on a string
  JsonDocument doc = parse_json_text(R"([{"components": {"Velocity": "fast"}}])", "v.json");
  EXPECT_ERROR_HAS(load_entities(doc.view(), world, reg), "v.json: $[0].components.Velocity: Velocity:");
}

TEST_F(Serialize, RegistrationErrors) {
  auto& reg = world.resource<ComponentRegistry>();
  auto to = [](const Health&) { return Json(); };
  auto from = [](const JsonView&) { return Health{}; };
  EXPECT_ERROR_HAS(reg.register_component<Health>("Health", to, from), "already registered");
  EXPECT_ERROR_HAS(reg.register_component<Health>("Health2", to, from), "same C++ type");
  EXPECT_ERROR_HAS(reg.register_component<Health>("name", to, from), "reserved");
  EXPECT_NE(reg.find<Health>(), nullptr);
  EXPECT_EQ(reg.find("Nope"), nullptr);
}

TEST_F(Serialize, EntryGivesEditorsTypeErasedAccess) {
  auto& reg = world.resource<ComponentRegistry>();
  Entity e = world.create();
  const ComponentRegistry::Entry* health = reg.find("Health");
  ASSERT_NE(health, nullptr);
  EXPECT_FALSE(health->has(world, e));
  JsonDocument doc = parse_json_text(R"({"hp": 12})", "panel");
  health->load(world, e, doc.view());
  EXPECT_EQ(world.get<Health>(e).hp, 12);
  EXPECT_EQ(health->save(world, e)["hp"], 12);
  EXPECT_TRUE(health->remove(world, e));
  EXPECT_FALSE(world.has<Health>(e));
}

TEST(SerializeNoRegistry, MissingRegistryResourceIsAClearError) {
  World w;
  EXPECT_ERROR_HAS(serialize_world(w), "ComponentRegistry");
}

}  // namespace
}  // namespace cumulo::ecs
