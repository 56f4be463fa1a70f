// Level loading: the sample level, component JSON forms, and errors that name the file and JSON path.
#include <gtest/gtest.h>

#include <functional>

#include "engine/core/file_io.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"
#include "engine/scene/level.h"
#include "engine/scene/serialization.h"
#include "engine/scene/sun.h"
#include "scene_test_util.h"

using namespace cumulo;
using namespace cumulo::scene;
using scene::test::expect_error;
using scene::test::temp_dir;
namespace fs = std::filesystem;

namespace {

fs::path sample_level() { return repo_root() / "content/levels/sample/level.json"; }

fs::path write_level(const fs::path& dir, const std::string& entities_json) {
  fs::path file = dir / "level.json";
  write_file_atomic(file, "{\n  \"version\": 1,\n  \"name\": \"t\",\n  \"entities\": " + entities_json + "\n}\n");
  return file;
}

}  // namespace

TEST(Level, SampleLevelLoadsWithCamerasSunAndTerrain) {
  ecs::World world;
  auto& reg = world.set_resource<ecs::ComponentRegistry>();
  scene::test::register_sample_level_components(reg);
  LevelInfo level = load_level(sample_level(), world);

  EXPECT_EQ(level.name, "sample");
  EXPECT_EQ(level.entities.size(), world.alive_count());
  for (const char* name : {"ground", "mixed", "immersed", "stormbird", "lair", "overview"}) {
    ecs::Entity cam = find_camera(world, name);
    EXPECT_TRUE(world.has<Camera>(cam)) << name;
    EXPECT_NE(std::find(level.cameras.begin(), level.cameras.end(), name), level.cameras.end()) << name;
  }

  ASSERT_EQ(level.models.size(), 1u);
  ecs::Entity terrain = world.find("archipelago");
  ASSERT_FALSE(terrain.is_null());
  const ModelRef& ref = world.get<ModelRef>(terrain);
  ASSERT_TRUE(ref.model);
  EXPECT_EQ(ref.resolved.filename(), "terrain.glb");
  EXPECT_EQ(ref.model->instances_with_material("terrain").size(), 4u);  // 2 x 2 tiles
  EXPECT_EQ(ref.model->instances_with_material("ocean").size(), 1u);
  EXPECT_NEAR(level.bounds.min.x, -20000.0f, 1.0f);  // the ocean quad
  EXPECT_NEAR(level.bounds.max.z, 20000.0f, 1.0f);
  EXPECT_GE(level.bounds.max.y, 200.0f);

  // The sun: late afternoon, in the western sky, above the horizon.
  SunLight sun = find_sun_light(world);
  EXPECT_GT(sun.elevation_deg, 5.0f);
  EXPECT_LT(sun.direction.x, 0.0f);
  const Ocean* ocean = world.try_get<Ocean>(world.find("ocean"));
  ASSERT_NE(ocean, nullptr);
  EXPECT_EQ(ocean->sea_level, 0.0f);
}

TEST(Level, LoadsWithADefaultRegistryWhenTheWorldHasNone) {
  ecs::World world;
  LevelInfo level = load_level(repo_root() / "tests/engine/scene/data/levels/small.json", world);
  EXPECT_EQ(level.cameras.size(), 1u);
  // The default registry knows the scene components only: a module's component is refused, by name.
  ecs::World other;
  expect_error([&] { load_level(sample_level(), other); }, {"WeatherScheduler"});  // the first one in file order
  EXPECT_EQ(other.alive_count(), 0u);
}

TEST(Level, ComponentJsonForms) {
  fs::path file = write_level(temp_dir(), R"([
    {"name": "a", "components": {"Transform": {"position": [1, 2, 3], "euler_deg": [0, 90, 0], "scale": 2}}},
    {"name": "b", "components": {"Transform": {"rotation": [0, 0, 0, 1], "scale": [1, 2, 3]},
                                 "Camera": {"fov_y_deg": 45, "near": 0.5, "far": 900}}},
    {"name": "c", "components": {"Transform": {"position": [0, 10, 0], "look_at": [0, 10, -5]},
                                 "TimeOfDay": {"hours": 24}, "Sun": {"illuminance": 3}}}
  ])");
  ecs::World world;
  load_level(file, world);
  const Transform& a = world.get<Transform>(world.find("a"));
  EXPECT_EQ(a.position, glm::vec3(1, 2, 3));
  EXPECT_EQ(a.scale, glm::vec3(2));
  EXPECT_LT(glm::length(a.forward() - glm::vec3(-1, 0, 0)), 1e-5f);
  const Camera& cam = world.get<Camera>(world.find("b"));
  EXPECT_EQ(cam.fov_y_deg, 45.0f);
  EXPECT_EQ(cam.near, 0.5f);
  EXPECT_EQ(cam.far, 900.0f);
  EXPECT_EQ(world.get<Transform>(world.find("b")).scale, glm::vec3(1, 2, 3));
  EXPECT_LT(glm::length(world.get<Transform>(world.find("c")).forward() - glm::vec3(0, 0, -1)), 1e-5f);
  EXPECT_EQ(world.get<TimeOfDay>(world.find("c")).hours, 0.0f);  // 24:00 is midnight
  EXPECT_EQ(world.get<Sun>(world.find("c")).illuminance, 3.0f);
}

TEST(Level, SaveThenLoadGivesTheSameComponents) {
  fs::path dir = temp_dir();
  ecs::ComponentRegistry reg;
  register_components(reg);
  ecs::World world;
  ecs::Entity e = world.create();
  world.emplace<ecs::Name>(e, ecs::Name{"cam"});
  world.emplace<Transform>(e, Transform::look_at({5, 6, 7}, {0, 100, 0}));
  world.emplace<Camera>(e, Camera{40.0f, 0.2f, 1234.0f});
  TimeOfDay tod;
  tod.hours = 7.25f;
  tod.latitude_deg = -12.0f;
  world.emplace<TimeOfDay>(e, tod);
  save_level(dir / "saved.json", world, reg, "saved");

  ecs::World again;
  LevelInfo info = load_level(dir / "saved.json", again, reg);
  EXPECT_EQ(info.name, "saved");
  ecs::Entity c = find_camera(again, "cam");
  const Transform& t = again.get<Transform>(c);
  EXPECT_LT(glm::length(t.position - glm::vec3(5, 6, 7)), 1e-5f);
  EXPECT_LT(glm::length(t.forward() - world.get<Transform>(e).forward()), 1e-5f);
  EXPECT_EQ(again.get<Camera>(c).far, 1234.0f);
  EXPECT_EQ(again.get<TimeOfDay>(c).hours, 7.25f);
  EXPECT_EQ(again.get<TimeOfDay>(c).latitude_deg, -12.0f);
}

TEST(Level, MissingAndMalformedLevelFilesAreNamed) {
  fs::path dir = temp_dir();
  ecs::World world;
  expect_error([&] { load_level(dir / "absent.json", world); }, {(dir / "absent.json").string()});

  fs::path bad = dir / "bad.json";
  write_file_atomic(bad, std::string("{\n  \"version\": 1,\n  \"entities\": [ {\"name\": \"x\",, } ]\n}\n"));
  expect_error([&] { load_level(bad, world); }, {bad.string() + ":3:"});
}

TEST(Level, BadValuesAreReportedAtTheirJsonPath) {
  fs::path dir = temp_dir();
  struct Case {
    const char* entities;
    std::vector<std::string> expect;
  };
  std::vector<Case> cases = {
      {R"([{"name": "g", "components": {"Camera": {"fov_y_deg": "wide"}}}])",
       {"$.entities[0].components.Camera.fov_y_deg", "expected a number"}},
      {R"([{"name": "g"}, {"name": "h", "components": {"Camera": {"fov_y_deg": 500}}}])",
       {"$.entities[1].components.Camera.fov_y_deg"}},
      {R"([{"components": {"Camera": {"near": 10, "far": 5}}}])", {"$.entities[0].components.Camera.far", "greater than near"}},
      {R"([{"components": {"Transform": {"postion": [0, 0, 0]}}}])",
       {"$.entities[0].components.Transform.postion", "unknown key", "position"}},
      {R"([{"components": {"Transform": {"position": [0, 0]}}}])", {"$.entities[0].components.Transform.position"}},
      {R"([{"components": {"Transform": {"rotation": [0, 0, 0, 2]}}}])", {"Transform.rotation", "unit quaternion"}},
      {R"([{"components": {"Transform": {"euler_deg": [0, 0, 0], "look_at": [1, 0, 0]}}}])", {"at most one"}},
      {R"([{"components": {"Cmaera": {}}}])", {"$.entities[0].components.Cmaera", "unknown component", "Camera"}},
      {R"([{"components": {"TimeOfDay": {"hours": 25}}}])", {"$.entities[0].components.TimeOfDay.hours"}},
      {R"([{"components": {"TimeOfDay": {"day_of_year": 0}}}])", {"TimeOfDay.day_of_year", "1..366"}},
      {R"([{"components": {"Sun": {"color": [1, -1, 1]}}}])", {"Sun.color[1]"}},
      {R"([{"components": {"ModelRef": {}}}])", {"$.entities[0].components.ModelRef", "path"}},
      {R"({"not": "an array"})", {"$.entities"}},
      // Outside numbers: finite as doubles but not floats (rendered a flat frame), and past a double.
      {R"([{"components": {"Camera": {"far": 1e39}}}])", {"$.entities[0].components.Camera.far", "does not fit a 32-bit float"}},
      {R"([{"components": {"Camera": {"far": 1e999999}}}])",
       {"$.entities[0].components.Camera.far", "1e999999 does not fit a 64-bit float"}},
      {R"([{"components": {"TimeOfDay": {"day_of_year": 4294967312}}}])", {"TimeOfDay.day_of_year", "does not fit"}},
      // Used to surface only as `no camera named "c"` for --camera c.
      {R"([{"name": "c", "components": {"Camera": {}}}])", {"$.entities[0].components.Camera", "needs a Transform"}},
  };
  for (const Case& c : cases) {
    fs::path file = write_level(dir, c.entities);
    std::vector<std::string> parts = c.expect;
    parts.push_back(file.string());
    ecs::World world;
    try {
      load_level(file, world);
      ADD_FAILURE() << "no error for " << c.entities;
    } catch (const Error& e) {
      std::string msg = e.what();
      for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing \"" << p << "\" in: " << msg;
    }
    EXPECT_EQ(world.alive_count(), 0u) << "a failed load must leave the world unchanged: " << c.entities;
  }
}

TEST(Level, UnsupportedVersionAndUnknownTopLevelKeys) {
  fs::path dir = temp_dir();
  ecs::World world;
  fs::path v2 = dir / "v2.json";
  write_file_atomic(v2, std::string(R"({"version": 2, "entities": []})"));
  expect_error([&] { load_level(v2, world); }, {v2.string(), "$.version", "unsupported level version 2"});
  fs::path extra = dir / "extra.json";
  write_file_atomic(extra, std::string(R"({"version": 1, "entities": [], "entites": []})"));
  expect_error([&] { load_level(extra, world); }, {"$.entites", "unknown key"});
}

TEST(Level, MissingOrBrokenModelNamesTheModelRefAndLeavesTheWorldAsItWas) {
  fs::path dir = temp_dir();
  ecs::World world;
  ecs::Entity keep = world.create();
  fs::path file = write_level(dir, R"([
    {"name": "cam", "components": {"Camera": {}, "Transform": {}}},
    {"name": "land", "components": {"ModelRef": {"path": "nowhere.glb"}}}
  ])");
  expect_error([&] { load_level(file, world); },
               {file.string(), "$.entities[1].components.ModelRef.path", "nowhere.glb", "not found"});
  EXPECT_EQ(world.alive_count(), 1u);
  EXPECT_TRUE(world.valid(keep));
  EXPECT_TRUE(world.find("cam").is_null());

  write_file_atomic(dir / "nowhere.glb", std::string("glTF but not really"));
  expect_error([&] { load_level(file, world); },
               {"$.entities[1].components.ModelRef.path", "nowhere.glb", "glTF parse error"});
  EXPECT_EQ(world.alive_count(), 1u);
}

TEST(Level, SmallTestLevelUsesEveryComponentForm) {
  ecs::World world;
  LevelInfo level = load_level(repo_root() / "tests/engine/scene/data/levels/small.json", world);
  EXPECT_EQ(level.cameras, (std::vector<std::string>{"cam"}));
  const ModelRef& ref = world.get<ModelRef>(world.find("model"));
  EXPECT_FALSE(ref.cast_shadows);
  ASSERT_TRUE(ref.model);
  EXPECT_EQ(ref.model->meshes.size(), 1u);
  // The model's bounds (x 10..12, z -2..0) scaled by (1, 2, 1).
  EXPECT_NEAR(level.bounds.min.x, 10.0f, 1e-4f);
  EXPECT_NEAR(level.bounds.min.z, -2.0f, 1e-4f);
  EXPECT_EQ(find_sun_light(world).elevation_deg, sun_position(*find_sun(world).time).elevation_deg);

  // Without models: entities only, the path resolved but not opened.
  ecs::World bare;
  ecs::ComponentRegistry reg;
  register_components(reg);
  JsonDocument doc = load_json_file(repo_root() / "tests/engine/scene/data/levels/small.json");
  LevelInfo info = load_level_document(doc, "/nonexistent/dir", bare, reg, false);
  EXPECT_EQ(info.models.size(), 0u);
  EXPECT_EQ(bare.get<ModelRef>(bare.find("model")).resolved, fs::path("/nonexistent/gltf/quad.gltf"));
}

// The shipped level schema documents the sample level: every "$ref" resolves, every component the level
// uses is a property of the schema's entity components, and every key it gives a component is one of that
// component's properties.
TEST(Level, SampleLevelKeysAreAllInTheLevelSchema) {
  const Json schema = Json::parse(read_file_text(repo_root() / "content/schemas/level.schema.json"));
  const Json level = Json::parse(read_file_text(sample_level()));
  std::function<void(const Json&, const std::string&)> refs = [&](const Json& j, const std::string& at) {
    if (j.is_object()) {
      if (j.contains("$ref")) {
        const std::string r = j["$ref"].get<std::string>();
        ASSERT_EQ(r.rfind("#/$defs/", 0), 0u) << at << ": " << r;
        EXPECT_TRUE(schema["$defs"].contains(r.substr(8))) << at << ": unresolved " << r;
      }
      for (const auto& [k, v] : j.items()) refs(v, at + "/" + k);
    } else if (j.is_array()) {
      for (size_t i = 0; i < j.size(); ++i) refs(j[i], at + "/" + std::to_string(i));
    }
  };
  refs(schema, "#");
  const Json& components = schema["$defs"]["entity"]["properties"]["components"]["properties"];
  for (const Json& e : level["entities"])
    for (const auto& [name, value] : e["components"].items()) {
      ASSERT_TRUE(components.contains(name)) << e["name"] << ": component " << name << " is not in the schema";
      const std::string ref = components[name]["$ref"].get<std::string>();
      const Json& def = schema["$defs"][ref.substr(8)];
      if (!def.contains("properties")) continue;
      for (const auto& [key, v] : value.items())
        EXPECT_TRUE(def["properties"].contains(key)) << e["name"] << ": " << name << "." << key << " is not in the schema";
    }
}
