// The sample archipelago: determinism of the generator, the committed .glb, and what the brief asks of it
// (4 km x 4 km, several islands, beaches, a 200 m peak, ocean) and of the sample level's cameras.
#include <gtest/gtest.h>

#include <queue>

#include "engine/core/file_io.h"
#include "engine/core/hash.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"
#include "engine/scene/gltf.h"
#include "engine/scene/level.h"
#include "engine/scene/tools/terrain_gen.h"
#include "tests/engine/scene/scene_test_util.h"

using namespace cumulo;
using namespace cumulo::scene;
namespace fs = std::filesystem;

namespace {

fs::path sample_dir() { return repo_root() / "content/levels/sample"; }

// The cloud layer the sample level is authored for (content/README.md): a 512 m tall cloudscape whose
// base is at 600 m.
constexpr float kCloudBase = 600.0f, kCloudTop = 1112.0f;

// Land regions of a heightfield (4-connected vertices above sea level), counting those of at least `min_cells`.
int count_islands(const Heightfield& hf, size_t min_cells) {
  uint32_t n = hf.resolution;
  std::vector<int> label(size_t(n) * n, -1);
  int islands = 0;
  for (uint32_t start = 0; start < n * n; ++start) {
    if (label[start] >= 0 || hf.heights[start] <= 0.0f) continue;
    size_t cells = 0;
    std::queue<uint32_t> q;
    q.push(start);
    label[start] = 1;
    while (!q.empty()) {
      uint32_t k = q.front();
      q.pop();
      ++cells;
      uint32_t i = k % n, j = k / n;
      auto visit = [&](uint32_t ii, uint32_t jj) {
        uint32_t kk = jj * n + ii;
        if (label[kk] < 0 && hf.heights[kk] > 0.0f) {
          label[kk] = 1;
          q.push(kk);
        }
      };
      if (i > 0) visit(i - 1, j);
      if (i + 1 < n) visit(i + 1, j);
      if (j > 0) visit(i, j - 1);
      if (j + 1 < n) visit(i, j + 1);
    }
    if (cells >= min_cells) ++islands;
  }
  return islands;
}

}  // namespace

TEST(Terrain, SameSeedSameBytesOtherSeedOtherBytes) {
  TerrainOptions o;
  o.resolution = 65;
  o.texture_size = 64;
  auto a = build_terrain_glb(o), b = build_terrain_glb(o);
  EXPECT_EQ(a, b);
  o.seed = 2;
  EXPECT_NE(build_terrain_glb(o), a);
}

TEST(Terrain, CommittedGlbMatchesTheGenerator) {
  // If this fails, the generator changed: run `cumulo gen-terrain -o content/levels/sample/terrain.glb`
  // and commit the new file (and re-check the cameras in level.json).
  std::vector<uint8_t> committed = read_file_bytes(sample_dir() / "terrain.glb");
  TerrainReport report;
  std::vector<uint8_t> fresh = build_terrain_glb(TerrainOptions{}, &report);
  EXPECT_EQ(committed.size(), fresh.size());
  EXPECT_EQ(hash64(committed.data(), committed.size()), hash64(fresh.data(), fresh.size()));
  EXPECT_LE(committed.size(), 4u * 1024 * 1024);
}

TEST(Terrain, SampleTerrainHasTheRequiredShape) {
  Model m = load_gltf(sample_dir() / "terrain.glb");
  Bounds land;
  size_t vertices = 0;
  for (const MeshInstance* inst : m.instances_with_material("terrain")) {
    land.add(m.meshes[inst->mesh].bounds.transformed(inst->world));
    vertices += m.meshes[inst->mesh].vertices.size();
  }
  // 4096 m x 4096 m centred on the origin, Y up, sea level 0.
  EXPECT_NEAR(land.min.x, -2048.0f, 0.01f);
  EXPECT_NEAR(land.max.x, 2048.0f, 0.01f);
  EXPECT_NEAR(land.min.z, -2048.0f, 0.01f);
  EXPECT_NEAR(land.max.z, 2048.0f, 0.01f);
  EXPECT_GE(land.max.y, 200.0f);  // the Burning Shores peak
  EXPECT_LT(land.min.y, -20.0f);  // sea floor
  EXPECT_EQ(vertices, 4u * 129u * 129u);  // 257 x 257 grid in 2 x 2 tiles (shared edges duplicated)
  for (const MeshInstance* inst : m.instances_with_material("terrain")) {
    const Mesh& mesh = m.meshes[inst->mesh];
    EXPECT_FALSE(mesh.generated_normals);
    EXPECT_EQ(mesh.indices.size(), 128u * 128u * 6u);
  }
  const Material* terrain_mat = nullptr;
  for (auto& mat : m.materials)
    if (mat.name == "terrain") terrain_mat = &mat;
  ASSERT_NE(terrain_mat, nullptr);
  ASSERT_GE(terrain_mat->base_color_texture, 0);
  const Texture& tex = m.textures[size_t(terrain_mat->base_color_texture)];
  EXPECT_EQ(tex.width, 512u);
  EXPECT_EQ(tex.height, 512u);

  // The ocean: a 40 km quad at y = 0 with a blue material.
  auto ocean = m.instances_with_material("ocean");
  ASSERT_EQ(ocean.size(), 1u);
  Bounds ob = m.meshes[ocean[0]->mesh].bounds.transformed(ocean[0]->world);
  EXPECT_NEAR(ob.size().x, 40000.0f, 1.0f);
  EXPECT_NEAR(ob.max.y, 0.0f, 1e-6f);
  int ocean_mat = m.meshes[ocean[0]->mesh].material;
  ASSERT_GE(ocean_mat, 0);
  glm::vec4 blue = m.materials[size_t(ocean_mat)].base_color_factor;
  EXPECT_GT(blue.b, blue.r);
  EXPECT_EQ(m.materials[size_t(ocean_mat)].base_color_texture, -1);
}

TEST(Terrain, ArchipelagoHasIslandsBeachesAndColours) {
  Archipelago arch{TerrainOptions{}};
  Heightfield hf = sample_heightfield(arch);
  EXPECT_GE(count_islands(hf, 50), 4);  // several islands of at least ~12,000 m^2

  // Beaches: shore vertices (0..3 m) that are gentle (under 10 degrees), and plenty of them.
  size_t beach = 0;
  float s = hf.spacing();
  for (uint32_t j = 1; j + 1 < hf.resolution; ++j)
    for (uint32_t i = 1; i + 1 < hf.resolution; ++i) {
      float h = hf.at(i, j);
      if (h <= 0.0f || h > 3.0f) continue;
      float dx = (hf.at(i + 1, j) - hf.at(i - 1, j)) / (2 * s), dz = (hf.at(i, j + 1) - hf.at(i, j - 1)) / (2 * s);
      if (std::sqrt(dx * dx + dz * dz) < std::tan(glm::radians(10.0f))) ++beach;
    }
  EXPECT_GT(beach, 300u);

  // The texture: sand on the beaches, green inland, grey-brown rock near the summit.
  Model m = load_gltf(sample_dir() / "terrain.glb");
  const Texture& tex = m.textures.at(0);
  auto texel = [&](float x, float z) {
    uint32_t tx = uint32_t((x + 2048.0f) / 4096.0f * float(tex.width));
    uint32_t ty = uint32_t((z + 2048.0f) / 4096.0f * float(tex.height));
    const uint8_t* p = &tex.rgba[(size_t(ty) * tex.width + tx) * 4];
    return glm::vec3(p[0], p[1], p[2]) / 255.0f;
  };
  size_t top = size_t(std::max_element(hf.heights.begin(), hf.heights.end()) - hf.heights.begin());
  glm::vec3 peak = hf.position(uint32_t(top % hf.resolution), uint32_t(top / hf.resolution));
  EXPECT_GE(peak.y, 200.0f);
  glm::vec3 summit = texel(peak.x, peak.z);
  EXPECT_LT(summit.g, 0.5f);                       // rock, not grass
  EXPECT_LT(std::abs(summit.r - summit.b), 0.15f);  // grey-ish
}

TEST(Terrain, SampleLevelCamerasSitWhereTheBriefSays) {
  Archipelago arch{TerrainOptions{}};
  Heightfield hf = sample_heightfield(arch);
  ecs::World world;
  ecs::ComponentRegistry reg;
  scene::test::register_sample_level_components(reg);
  load_level(sample_dir() / "level.json", world, reg);

  // ground: on a beach, about 2 m up, looking 20-30 degrees up at the sky.
  const Transform& ground = world.get<Transform>(find_camera(world, "ground"));
  float below = hf.sample(ground.position.x, ground.position.z);
  EXPECT_GT(below, 0.0f);
  EXPECT_LT(below, 4.0f);
  EXPECT_NEAR(ground.position.y - below, 2.0f, 0.5f);
  float pitch = glm::degrees(std::asin(ground.forward().y));
  EXPECT_GE(pitch, 20.0f);
  EXPECT_LE(pitch, 30.0f);

  // mixed: in the air between the terrain and the cloud base.
  const Transform& mixed = world.get<Transform>(find_camera(world, "mixed"));
  EXPECT_GE(mixed.position.y, 300.0f);
  EXPECT_LT(mixed.position.y, kCloudBase);
  EXPECT_GT(mixed.position.y - hf.sample(mixed.position.x, mixed.position.z), 100.0f);

  // immersed: inside the cloud layer, within the cloudscape's 4096 m square.
  const Transform& immersed = world.get<Transform>(find_camera(world, "immersed"));
  EXPECT_GT(immersed.position.y, kCloudBase);
  EXPECT_LT(immersed.position.y, kCloudTop);
  // stormbird: below the cloud base, clear of the terrain, outside the storm cloud (about 1.4 km from it);
  // lair: in the storm cloud's chamber (the clouds module's tests check the chamber is air there).
  const Transform& stormbird = world.get<Transform>(find_camera(world, "stormbird"));
  EXPECT_LT(stormbird.position.y, kCloudBase);
  EXPECT_GT(stormbird.position.y - hf.sample(stormbird.position.x, stormbird.position.z), 100.0f);
  const Transform& lair = world.get<Transform>(find_camera(world, "lair"));
  EXPECT_GT(lair.position.y, kCloudBase);
  EXPECT_LT(lair.position.y, kCloudTop);
  for (const Transform* t : {&ground, &mixed, &immersed, &stormbird, &lair}) {
    EXPECT_LT(std::abs(t->position.x), 2048.0f);
    EXPECT_LT(std::abs(t->position.z), 2048.0f);
  }
}
