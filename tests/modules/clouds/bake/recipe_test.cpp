// Recipe parsing: structure, defaults, and errors that name the file and the JSON path.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "engine/core/error.h"
#include "modules/clouds/bake/compose.h"
#include "modules/clouds/bake/grid_sdf.h"
#include "modules/clouds/bake/recipe.h"
#include "tests/support/temp_dir.h"

using namespace cumulo::clouds::bake;

namespace {

std::string error_of(const std::string& text) {
  try {
    parse_recipe_text(text, "test.json", ".");
  } catch (const cumulo::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Recipe, ParsesEditsTransformsAndDefaults) {
  Recipe r = parse_recipe_text(R"({
    "name": "t", "seed": 3, "voxel_size": 16,
    "bounds": {"min": [-512, 0, -512], "max": [512, 256, 512]},
    "defaults": {"detail_type": 0.25, "density_scale": 0.5},
    "edits": [
      {"type": "sphere", "radius": 100, "position": [0, 120, 0], "detail_type": 0.9},
      {"type": "metaball", "radius": 40, "position": [90, 120, 0]},
      {"type": "ellipsoid", "radii": [200, 50, 100], "scale": [1, 0.5, 1], "shear": [0.2, 0]},
      {"type": "box", "size": [100, 40, 60], "rounding": 10, "rotation": [0, 45, 0], "op": "subtract", "blend": 8},
      {"type": "capsule", "a": [0, 0, 0], "b": [0, 100, 0], "radius": 20, "erode": {"amplitude": 10, "frequency": 0.02}},
      {"type": "particles", "points": [[0, 100, 0, 10], [20, 100, 0, 12]], "particle_blend": 5},
      {"type": "group", "position": [100, 0, 0], "density_scale": 0.8, "edits": [
        {"type": "sphere", "radius": 10},
        {"type": "particles", "generate": {"count": 50, "radii": [40, 10, 40], "radius": [3, 6]}}]}
    ]})",
                               "t.json", ".");
  EXPECT_EQ(r.seed, 3u);
  EXPECT_EQ(r.edits.size(), 7u);
  EXPECT_EQ(r.edits[0].detail_type, 0.9f);
  EXPECT_EQ(r.edits[0].density_scale, 0.5f);  // recipe default
  EXPECT_EQ(r.edits[1].blend, 20.0f);          // metaball: half its radius by default
  EXPECT_EQ(r.edits[3].op, EditOp::Subtract);
  EXPECT_EQ(r.edits[6].children[0].density_scale, 0.8f);  // inherited from the group
  EXPECT_EQ(r.edits[6].children[1].particles.size(), 50u);
  EXPECT_EQ(r.edits[2].transform.min_scale(), 0.5f);
  // Bounds include the shape, the blend radius and the band.
  EXPECT_TRUE(r.edits[0].parent_bounds.contains({0, 120 + 100 + 20, 0}));
  EXPECT_FALSE(r.edits[0].parent_bounds.contains({0, 120 + 100 + 60, 0}));
}

TEST(Recipe, SeedOverrideChangesGeneratedParticles) {
  const char* text = R"({"edits": [{"type": "particles", "generate": {"count": 10, "radii": [40, 10, 40], "radius": [3, 6]}}]})";
  Recipe a = parse_recipe_text(text, "a", "."), b = parse_recipe_text(text, "a", ".");
  RecipeOptions o;
  o.seed = 99;
  Recipe c = parse_recipe_text(text, "a", ".", o);
  EXPECT_EQ(a.edits[0].particles[3].center, b.edits[0].particles[3].center);
  EXPECT_NE(a.edits[0].particles[3].center, c.edits[0].particles[3].center);
  EXPECT_EQ(c.seed, 99u);
}

TEST(Recipe, ErrorsNameTheFileAndJsonPath) {
  EXPECT_EQ(error_of(R"({"edits": [{"type": "sphere"}]})"), "test.json: $.edits[0]: missing required member \"radius\"");
  EXPECT_NE(error_of(R"({"edits": [{"type": "sphere", "radius": "big"}]})").find("test.json: $.edits[0].radius: expected a number"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "sphere", "radius": -3}]})").find("$.edits[0].radius"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "sphere", "radus": 3, "radius": 4}]})").find("$.edits[0].radus: unknown member"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "cone", "radius": 3}]})").find("$.edits[0].type"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "sphere", "radius": 3, "op": "xor"}]})").find("$.edits[0].op"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "group", "edits": [{"type": "sphere", "radius": 1}, {"type": "ellipsoid", "radii": [1, 2]}]}]})")
                .find("$.edits[0].edits[1].radii: expected an array of 3 numbers"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "box", "size": [10, 10, 10], "rounding": 8}]})").find("$.edits[0].rounding"), std::string::npos);
  EXPECT_NE(error_of(R"({"bounds": {"min": [0, 0, 0], "max": [10, -1, 10]}, "edits": []})").find("$.bounds.max[1]"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "mesh", "file": "nope.gltf"}]})").find("$.edits[0].file"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "volume", "file": "nope.nvdf"}]})").find("$.edits[0].file"), std::string::npos);
  EXPECT_NE(error_of(R"({"edits": [{"type": "particles", "points": [[0, 0, 0, 0]]}]})").find("$.edits[0].points[0][3]"), std::string::npos);
  EXPECT_NE(error_of("{\"edits\": [\n  {\"type\": }]}").find("test.json:2:"), std::string::npos);  // syntax: line:col
  EXPECT_NE(error_of(R"({})").find("test.json: $: missing required member \"edits\""), std::string::npos);
}

// The coverage threshold (issue 20): per edit, inherited from the group and the recipe's defaults like
// detail_type; 0..1, every bad value named by file and JSON path.
TEST(Recipe, CoverageThresholdsAreInheritedAndRangeChecked) {
  Recipe r = parse_recipe_text(R"({
    "defaults": {"coverage": 0.25},
    "edits": [
      {"type": "sphere", "radius": 10, "coverage": 0.6},
      {"type": "sphere", "radius": 10},
      {"type": "group", "coverage": 0.8, "edits": [{"type": "sphere", "radius": 5}, {"type": "sphere", "radius": 5, "coverage": 0}]}
    ]})",
                               "t.json", ".");
  EXPECT_EQ(r.default_coverage, 0.25f);
  EXPECT_EQ(r.edits[0].coverage, 0.6f);
  EXPECT_EQ(r.edits[1].coverage, 0.25f);  // the recipe's default
  EXPECT_EQ(r.edits[2].children[0].coverage, 0.8f);  // the group's
  EXPECT_EQ(r.edits[2].children[1].coverage, 0.0f);
  EXPECT_EQ(parse_recipe_text(R"({"edits": [{"type": "sphere", "radius": 1}]})", "t.json", ".").edits[0].coverage, 0.0f);

  EXPECT_EQ(error_of(R"({"edits": [{"type": "sphere", "radius": 3, "coverage": 1.5}]})"),
            "test.json: $.edits[0].coverage: value 1.5 out of range [0, 1]");
  EXPECT_EQ(error_of(R"({"edits": [{"type": "sphere", "radius": 3, "coverage": -0.1}]})"),
            "test.json: $.edits[0].coverage: value -0.1 out of range [0, 1]");
  EXPECT_NE(error_of(R"({"edits": [{"type": "sphere", "radius": 3, "coverage": "high"}]})")
                .find("test.json: $.edits[0].coverage: expected a number"),
            std::string::npos);
  EXPECT_EQ(error_of(R"({"edits": [{"type": "group", "edits": [{"type": "sphere", "radius": 1, "coverage": 2}]}]})"),
            "test.json: $.edits[0].edits[0].coverage: value 2 out of range [0, 1]");
  EXPECT_EQ(error_of(R"({"defaults": {"coverage": 7}, "edits": []})"), "test.json: $.defaults.coverage: value 7 out of range [0, 1]");
  EXPECT_NE(error_of(R"({"defaults": {"coverag": 0.5}, "edits": []})").find("$.defaults.coverag: unknown member"), std::string::npos);
}

#ifdef CUMULO_BAKE_TEST_HAS_SCENE
namespace {
float sd_round_box_ref(glm::vec3 p) {
  glm::vec3 q = glm::abs(p) - glm::vec3(50.0f);
  return glm::length(glm::max(q, 0.0f)) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
}
}  // namespace

TEST(Recipe, MeshEditVoxelizesAGltfCube) {
  // A unit cube (12 triangles) as a .gltf with an embedded base64 buffer.
  std::vector<float> pos = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1};
  std::vector<uint16_t> idx = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                               2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
  std::string bin(reinterpret_cast<const char*>(pos.data()), pos.size() * 4);
  bin.append(reinterpret_cast<const char*>(idx.data()), idx.size() * 2);
  static const char* b64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string enc;
  for (size_t i = 0; i < bin.size(); i += 3) {
    uint32_t v = uint8_t(bin[i]) << 16 | (i + 1 < bin.size() ? uint8_t(bin[i + 1]) << 8 : 0) | (i + 2 < bin.size() ? uint8_t(bin[i + 2]) : 0);
    enc += b64[v >> 18], enc += b64[(v >> 12) & 63];
    enc += i + 1 < bin.size() ? b64[(v >> 6) & 63] : '=';
    enc += i + 2 < bin.size() ? b64[v & 63] : '=';
  }
  std::filesystem::path dir = cumulo::test::unique_temp_path("cumulo_bake_mesh_test");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cube.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"byteLength": )" << bin.size() << R"(, "uri": "data:application/octet-stream;base64,)" << enc << R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-1, -1, -1], "max": [1, 1, 1]},
                  {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]})";
  std::ofstream(dir / "r.json") << R"({"edits": [{"type": "mesh", "file": "cube.gltf", "resolution": 0.1, "scale": 50, "position": [0, 200, 0]}]})";
  Recipe r = load_recipe(dir / "r.json");
  ASSERT_TRUE(r.edits[0].grid);
  // A 100 m cube centred at y = 200: the mesh distance matches the box's.
  for (glm::vec3 p : {glm::vec3(0, 200, 0), glm::vec3(30, 220, -10), glm::vec3(70, 200, 0), glm::vec3(0, 265, 0), glm::vec3(48, 200, 0)}) {
    float want = sd_round_box_ref(p - glm::vec3(0, 200, 0));
    EXPECT_NEAR(evaluate_point(r, p).d, want, 5.0f) << p.x << " " << p.y;
  }
  std::filesystem::remove_all(dir);
}
#endif

// ---- outside numbers and files (issue: hardening every loader) ---------------------------------------

TEST(Recipe, NumbersOutsideTheirTypeOrRangeAreRefusedWithTheirPath) {
  // 1e999999 overflows a double (nlohmann's out_of_range.406): named like any other bad value.
  std::string e = error_of(R"({"edits": [{"type": "sphere", "radius": 1e999999}]})");
  EXPECT_NE(e.find("test.json:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("$.edits[0].radius"), std::string::npos) << e;
  EXPECT_EQ(e.find("json.exception"), std::string::npos) << e;
  // 1e39 is a double but not a float: it used to become inf and bake to nothing.
  e = error_of(R"({"edits": [{"type": "particles", "points": [[0, 100, 0, 1e39]]}]})");
  EXPECT_NE(e.find("$.edits[0].points[0][3]: 1e+39 does not fit a 32-bit float"), std::string::npos) << e;
  // A tiny radius made the particle bins overflow an int (recipe_fuzz); a tiny scale does the same.
  e = error_of(R"({"edits": [{"type": "particles", "points": [[1000, 100, 0, 1e-40]]}]})");
  EXPECT_NE(e.find("$.edits[0].points[0][3]: particle radius"), std::string::npos) << e;
  e = error_of(R"({"edits": [{"type": "particles", "generate": {"count": 3, "radii": [1, 1, 1], "radius": [1e-30, 1]}}]})");
  EXPECT_NE(e.find("$.edits[0].generate.radius"), std::string::npos) << e;
  e = error_of(R"({"edits": [{"type": "sphere", "radius": 5, "scale": 1e-30}]})");
  EXPECT_NE(e.find("$.edits[0].scale: scale"), std::string::npos) << e;
  e = error_of(R"({"seed": 18446744073709551616, "edits": []})");
  EXPECT_NE(e.find("$.seed"), std::string::npos) << e;
}

TEST(Recipe, VolumeEditNamingADeviceIsRefused) {
  // /dev/zero never ends: reading it grew memory until std::bad_alloc, which named nothing.
  std::string e = error_of(R"({"edits": [{"type": "volume", "file": "/dev/zero"}]})");
  EXPECT_NE(e.find("test.json: $.edits[0].file: /dev/zero: not a regular file"), std::string::npos) << e;
}

TEST(Recipe, HugeValuesAreNotEchoedBack) {
  const std::string big(2 << 20, 'k');
  std::string e = error_of(R"({"edits": [{"type": "sphere", "radius": 3, ")" + big + R"(": 1}]})");
  EXPECT_NE(e.find("unknown member"), std::string::npos) << e.substr(0, 300);
  EXPECT_LT(e.size(), 400u);
  e = error_of(R"({"edits": [{"type": ")" + big + R"("}]})");
  EXPECT_NE(e.find("(2097152 bytes)"), std::string::npos) << e.substr(0, 300);
  EXPECT_LT(e.size(), 400u);
}
