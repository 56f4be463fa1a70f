// glTF loading: assets written by the test itself (GlbWriter), in .glb and .gltf form, good and broken.
#include <gtest/gtest.h>

#include <fstream>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/file_io.h"
#include "engine/core/png.h"
#include "engine/scene/gltf.h"
#include "engine/scene/tools/glb_writer.h"
#include "scene_test_util.h"

using namespace cumulo;
using namespace cumulo::scene;
using scene::test::expect_error;
using scene::test::temp_dir;
namespace fs = std::filesystem;

namespace {

enum class IndexType { U8, U16, U32 };

// A unit quad in the x-z plane (no normals: the loader must generate them), used by two nodes: a child
// under a translated parent (rotated 90 degrees about Y, scaled 2) and a node with a matrix.
// A 2x2 texture (red, green / blue, white) with a NEAREST, CLAMP sampler and a base-color factor.
GlbWriter make_asset(IndexType type = IndexType::U16) {
  GlbWriter w;
  std::vector<glm::vec3> pos = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +Y
  int ind;
  if (type == IndexType::U16) {
    std::vector<uint16_t> i16(idx.begin(), idx.end());
    ind = w.add_indices_u16(i16);
  } else if (type == IndexType::U32) {
    ind = w.add_indices_u32(idx);
  } else {
    std::vector<uint8_t> i8(idx.begin(), idx.end());
    int view = w.add_view(i8, 34963);
    w.json()["accessors"].push_back({{"bufferView", view}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}});
    ind = int(w.json()["accessors"].size()) - 1;
  }
  int p = w.add_vec3(pos, true), t = w.add_vec2(uv);
  std::vector<uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  int image = w.add_png_image(encode_png(rgb.data(), 2, 2, 3), "checker");
  auto& j = w.json();
  j["meshes"] = {{{"name", "quad"},
                  {"primitives", {{{"attributes", {{"POSITION", p}, {"TEXCOORD_0", t}}}, {"indices", ind}, {"material", 0}}}}}};
  j["materials"] = {{{"name", "tinted"},
                     {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}, {"baseColorTexture", {{"index", 0}}}}},
                     {"doubleSided", true}}};
  j["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33648}}};
  j["textures"] = {{{"sampler", 0}, {"source", image}}};
  j["nodes"] = {{{"name", "parent"}, {"translation", {10, 0, 0}}, {"children", {1}}},
                {{"name", "child"}, {"mesh", 0}, {"rotation", {0, 0.70710678, 0, 0.70710678}}, {"scale", {2, 2, 2}}},
                {{"name", "lifted"}, {"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}}};
  j["scenes"] = {{{"nodes", {0, 2}}}};
  j["scene"] = 0;
  return w;
}

fs::path write(const fs::path& path, const std::vector<uint8_t>& bytes) {
  write_file_atomic(path, bytes);
  return path;
}
fs::path write(const fs::path& path, const std::string& text) {
  write_file_atomic(path, text);
  return path;
}

bool near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-4f) { return glm::length(a - b) < eps; }

}  // namespace

TEST(Gltf, LoadsGlbWithHierarchyTextureFactorAndGeneratedNormals) {
  fs::path file = write(temp_dir() / "quad.glb", make_asset().finish());
  Model m = load_gltf(file);

  ASSERT_EQ(m.meshes.size(), 1u);
  const Mesh& mesh = m.meshes[0];
  EXPECT_EQ(mesh.name, "quad");
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 2, 1, 0, 3, 2}));
  EXPECT_TRUE(mesh.generated_normals);
  for (const Vertex& v : mesh.vertices) EXPECT_TRUE(near(v.normal, {0, 1, 0})) << v.normal.x << " " << v.normal.y;
  EXPECT_EQ(mesh.vertices[2].uv, glm::vec2(1, 1));
  EXPECT_EQ(mesh.material, 0);

  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].name, "tinted");
  EXPECT_EQ(m.materials[0].base_color_factor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
  EXPECT_EQ(m.materials[0].base_color_texture, 0);
  EXPECT_TRUE(m.materials[0].double_sided);

  ASSERT_EQ(m.textures.size(), 1u);
  const Texture& tex = m.textures[0];
  ASSERT_EQ(tex.width, 2u);
  ASSERT_EQ(tex.height, 2u);
  ASSERT_EQ(tex.rgba.size(), 16u);
  EXPECT_EQ(std::vector<uint8_t>(tex.rgba.begin(), tex.rgba.begin() + 4), (std::vector<uint8_t>{255, 0, 0, 255}));
  EXPECT_EQ(std::vector<uint8_t>(tex.rgba.begin() + 8, tex.rgba.begin() + 12), (std::vector<uint8_t>{0, 0, 255, 255}));
  EXPECT_FALSE(tex.linear_filter);
  EXPECT_EQ(tex.wrap_u, Wrap::ClampToEdge);
  EXPECT_EQ(tex.wrap_v, Wrap::MirroredRepeat);

  // Two instances of the one mesh: parent * child TRS, and the matrix node.
  ASSERT_EQ(m.instances.size(), 2u);
  glm::mat4 expected = glm::translate(glm::mat4(1), {10, 0, 0}) *
                       glm::rotate(glm::mat4(1), glm::radians(90.0f), {0, 1, 0}) * glm::scale(glm::mat4(1), {2, 2, 2});
  EXPECT_EQ(m.instances[0].node, "child");
  EXPECT_TRUE(near(glm::vec3(m.instances[0].world * glm::vec4(1, 0, 0, 1)), glm::vec3(expected * glm::vec4(1, 0, 0, 1))));
  EXPECT_TRUE(near(glm::vec3(m.instances[0].world * glm::vec4(1, 0, 0, 1)), {10, 0, -2}));
  EXPECT_EQ(m.instances[1].node, "lifted");
  EXPECT_TRUE(near(glm::vec3(m.instances[1].world * glm::vec4(1, 0, 1, 1)), {1, 5, 1}));

  // Bounds: the child spans x 10..12, z -2..0 at y 0; the lifted copy x 0..1, z 0..1 at y 5.
  EXPECT_TRUE(near(m.bounds.min, {0, 0, -2}));
  EXPECT_TRUE(near(m.bounds.max, {12, 5, 1}));
  EXPECT_EQ(m.vertex_count(), 4u);
  EXPECT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.instances_with_material("tinted").size(), 2u);
}

TEST(Gltf, IndexTypesU8U16U32GiveTheSameMesh) {
  auto load = [](IndexType t) {
    auto bytes = make_asset(t).finish();
    return load_gltf_from_memory(bytes, "mem.glb", {});
  };
  Model a = load(IndexType::U8), b = load(IndexType::U16), c = load(IndexType::U32);
  EXPECT_EQ(a.meshes[0].indices, b.meshes[0].indices);
  EXPECT_EQ(b.meshes[0].indices, c.meshes[0].indices);
}

TEST(Gltf, LoadsGltfWithExternalBufferAndImage) {
  fs::path dir = temp_dir();
  GlbWriter w = make_asset(IndexType::U8);
  std::vector<uint8_t> rgb = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120};
  write(dir / "tex.png", encode_png(rgb.data(), 2, 2, 3));
  w.json()["images"][0] = {{"uri", "tex.png"}};
  write(dir / "quad.bin", w.bin());
  fs::path file = write(dir / "quad.gltf", w.finish_gltf("quad.bin"));
  Model m = load_gltf(file);
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(std::vector<uint8_t>(m.textures[0].rgba.begin() + 4, m.textures[0].rgba.begin() + 8),
            (std::vector<uint8_t>{40, 50, 60, 255}));
  EXPECT_EQ(m.meshes[0].indices.size(), 6u);

  // The same file without its buffer, or without its image: errors that name the glTF.
  fs::remove(dir / "tex.png");
  expect_error([&] { load_gltf(file); }, {file.string(), "tex.png"});
  fs::remove(dir / "quad.bin");
  expect_error([&] { load_gltf(file); }, {file.string(), "quad.bin"});
}

TEST(Gltf, ExplicitNormalsAreKeptAndNormalized) {
  GlbWriter w = make_asset();
  std::vector<glm::vec3> nor(4, glm::vec3(0, 0, 2));
  int n = w.add_vec3(nor, false);
  w.json()["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = n;
  auto bytes = w.finish();
  Model m = load_gltf_from_memory(bytes, "mem.glb", {});
  EXPECT_FALSE(m.meshes[0].generated_normals);
  EXPECT_TRUE(near(m.meshes[0].vertices[0].normal, {0, 0, 1}));
}

TEST(Gltf, TriangleStripsAndFansAreUnrolled) {
  GlbWriter w = make_asset();
  std::vector<uint16_t> strip = {0, 3, 1, 2};
  int s = w.add_indices_u16(strip);
  w.json()["meshes"][0]["primitives"][0]["indices"] = s;
  w.json()["meshes"][0]["primitives"][0]["mode"] = 5;
  auto bytes = w.finish();
  Model m = load_gltf_from_memory(bytes, "strip.glb", {});
  EXPECT_EQ(m.meshes[0].indices, (std::vector<uint32_t>{0, 3, 1, 1, 3, 2}));  // winding kept for odd triangles

  w.json()["meshes"][0]["primitives"][0]["mode"] = 6;
  std::vector<uint16_t> fan = {0, 3, 2, 1};
  w.json()["meshes"][0]["primitives"][0]["indices"] = w.add_indices_u16(fan);
  bytes = w.finish();
  m = load_gltf_from_memory(bytes, "fan.glb", {});
  EXPECT_EQ(m.meshes[0].indices, (std::vector<uint32_t>{0, 3, 2, 0, 2, 1}));
}

TEST(Gltf, MissingFileIsNamed) {
  fs::path file = temp_dir() / "nowhere.glb";
  expect_error([&] { load_gltf(file); }, {file.string()});
}

TEST(Gltf, GarbageAndTruncatedFilesGiveParseErrors) {
  fs::path dir = temp_dir();
  fs::path garbage = write(dir / "garbage.gltf", std::string("{ this is not json"));
  // Our JSON gate runs before tinygltf: the line and column of the syntax error.
  expect_error([&] { load_gltf(garbage); }, {garbage.string() + ":1:4: JSON syntax error"});

  auto bytes = make_asset().finish();
  bytes.resize(bytes.size() / 2);
  fs::path truncated = write(dir / "truncated.glb", bytes);
  std::string msg = expect_error([&] { load_gltf(truncated); }, {truncated.string()});
  EXPECT_TRUE(msg.find("glTF parse error") != std::string::npos || msg.find("JSON syntax error") != std::string::npos) << msg;
}

// ---- hostile structure (issue: hardening every loader) -----------------------------------------------
namespace {
std::string gltf_with_nodes(const std::string& nodes, const std::string& extra = "") {
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": )" + nodes + extra + "}";
}
Model load_text(const std::string& text, const std::string& name) {
  return load_gltf_from_memory({reinterpret_cast<const uint8_t*>(text.data()), text.size()}, name, {});
}
}  // namespace

TEST(Gltf, DeepNodeChainIsWalkedWithoutRecursion) {
  // 200,000 nodes, each the only child of the one before: the recursive visit overflowed the stack.
  const int n = 200000;
  std::string nodes = "[";
  for (int i = 0; i < n; ++i) nodes += (i ? "," : "") + (i + 1 < n ? strf(R"({"children":[%d]})", i + 1) : std::string("{}"));
  nodes += "]";
  Model m = load_text(gltf_with_nodes(nodes), "chain.gltf");
  EXPECT_TRUE(m.instances.empty());  // no meshes, but every node was visited without a crash
  // A cycle at the end of the chain is still found.
  nodes.replace(nodes.size() - 3, 2, R"({"children":[0]})");
  expect_error([&] { load_text(gltf_with_nodes(nodes), "cycle.gltf"); }, {"cycle.gltf", "cycle"});
}

TEST(Gltf, SharedChildrenCannotMultiplyWithoutBound) {
  // Every node lists the next one twice: 2^40 paths from a 41-node file.
  std::string nodes = "[";
  for (int i = 0; i < 40; ++i) nodes += strf(R"({"children":[%d,%d]},)", i + 1, i + 1);
  nodes += "{}]";
  expect_error([&] { load_text(gltf_with_nodes(nodes), "shared.gltf"); }, {"shared.gltf", "node visits"});
}

TEST(Gltf, DeepJsonIsRefusedBeforeTinygltf) {
  // tinygltf converts "extras" recursively: 20,000 levels crashed it.
  const std::string deep = std::string(20000, '[') + std::string(20000, ']');
  expect_error([&] { load_text(gltf_with_nodes(R"([{"extras": )" + deep + "}]"), "deep.gltf"); },
               {"deep.gltf:1:", "nested deeper than 256 levels"});
  // The same inside a .glb's JSON chunk.
  GlbWriter w = make_asset();
  w.json()["extras"] = nlohmann::json::parse(std::string(300, '[') + std::string(300, ']'));
  const std::vector<uint8_t> glb = w.finish();
  expect_error([&] { load_gltf_from_memory(glb, "deep.glb", {}); }, {"deep.glb:1:", "nested deeper than 256 levels"});
}

TEST(Gltf, NumbersMustFitTheFloatsTheyBecome) {
  std::string msg = expect_error([&] { load_text(gltf_with_nodes("[{\"translation\": [1e999999, 0, 0]}]"), "big.gltf"); },
                                 {"big.gltf:1:", "$.nodes[0].translation[0]", "1e999999 does not fit a 64-bit float"});
  EXPECT_EQ(msg.find("json.exception"), std::string::npos) << msg;
  expect_error([&] { load_text(gltf_with_nodes("[{\"translation\": [1e39, 0, 0]}]"), "far.gltf"); },
               {"far.gltf: nodes[0].translation: 1e+39 does not fit a 32-bit float"});
}

TEST(Gltf, UnsupportedPrimitiveModesAreRefused) {
  GlbWriter w = make_asset();
  w.json()["meshes"][0]["primitives"][0]["mode"] = 1;
  auto bytes = w.finish();
  expect_error([&] { load_gltf_from_memory(bytes, "lines.glb", {}); },
               {"lines.glb", "meshes[0].primitives[0]", "unsupported primitive mode LINES"});
  w.json()["meshes"][0]["primitives"][0]["mode"] = 0;
  bytes = w.finish();
  expect_error([&] { load_gltf_from_memory(bytes, "points.glb", {}); }, {"POINTS"});
}

TEST(Gltf, OutOfRangeAccessorsAndIndicesAreRefused) {
  {
    GlbWriter w = make_asset();
    int pos = w.json()["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    w.json()["accessors"][size_t(pos)]["count"] = 4000;  // far past the end of its bufferView
    auto bytes = w.finish();
    expect_error([&] { load_gltf_from_memory(bytes, "big.glb", {}); }, {"big.glb", "accessors["});
  }
  {
    GlbWriter w = make_asset();
    std::vector<uint16_t> bad = {0, 1, 9};
    w.json()["meshes"][0]["primitives"][0]["indices"] = w.add_indices_u16(bad);
    auto bytes = w.finish();
    expect_error([&] { load_gltf_from_memory(bytes, "idx.glb", {}); }, {"idx.glb", "index 9", "out of range"});
  }
  {
    GlbWriter w = make_asset();
    w.json()["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 77;
    auto bytes = w.finish();
    expect_error([&] { load_gltf_from_memory(bytes, "acc.glb", {}); }, {"acc.glb"});
  }
}

TEST(Gltf, RequiredExtensionsAreRefused) {
  GlbWriter w = make_asset();
  w.json()["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  w.json()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  auto bytes = w.finish();
  expect_error([&] { load_gltf_from_memory(bytes, "draco.glb", {}); }, {"draco.glb", "KHR_draco_mesh_compression"});
}

TEST(Gltf, MemoryLoadsWithoutBaseDirectoryRefuseExternalFiles) {
  GlbWriter w = make_asset();
  auto text = w.finish_gltf("/etc/passwd");
  std::vector<uint8_t> bytes(text.begin(), text.end());
  expect_error([&] { load_gltf_from_memory(bytes, "ext.gltf", {}); }, {"ext.gltf"});
}

TEST(Gltf, GenerateNormalsWeighsByArea) {
  // Two triangles sharing vertex 0: a large one facing +Y and a small one facing +X.
  std::vector<Vertex> v(5);
  v[0].position = {0, 0, 0};
  v[1].position = {0, 0, 10};
  v[2].position = {10, 0, 0};
  v[3].position = {0, 1, 0};
  v[4].position = {0, 0, 1};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 3, 4};
  generate_normals(v, idx);
  EXPECT_TRUE(near(v[1].normal, {0, 1, 0}));
  EXPECT_TRUE(near(v[3].normal, {1, 0, 0}));
  EXPECT_GT(v[0].normal.y, 0.99f);  // the big face dominates
}

// Robustness in the spirit of a fuzzer, runnable with GCC: thousands of corrupted copies of a valid asset
// (byte flips, byte runs, truncations, in both the JSON and the binary chunk). Each must either load or be
// refused with a cumulo::Error; any crash, hang or other exception fails the test.
TEST(Gltf, CorruptedAssetsLoadOrFailCleanly) {
  std::vector<uint8_t> good = make_asset().finish();
  uint64_t state = 12345;
  auto rnd = [&](uint64_t n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (state >> 33) % n;
  };
  int loaded = 0, refused = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    std::vector<uint8_t> bytes = good;
    switch (rnd(4)) {
      case 0:  // a few random bytes
        for (int k = 0, n = 1 + int(rnd(4)); k < n; ++k) bytes[rnd(bytes.size())] = uint8_t(rnd(256));
        break;
      case 1: {  // a digit in the JSON replaced by another: counts, offsets, indices out of range
        size_t at = rnd(bytes.size());
        while (at < bytes.size() && !(bytes[at] >= '0' && bytes[at] <= '9')) ++at;
        if (at < bytes.size()) bytes[at] = uint8_t('0' + rnd(10));
        break;
      }
      case 2:  // truncation
        bytes.resize(rnd(bytes.size()));
        break;
      default: {  // a run of 0xFF or 0x00
        size_t at = rnd(bytes.size()), len = 1 + rnd(16);
        uint8_t v = rnd(2) ? 0xFF : 0x00;
        for (size_t k = at; k < bytes.size() && k < at + len; ++k) bytes[k] = v;
      }
    }
    try {
      Model m = load_gltf_from_memory(bytes, "fuzz.glb", {});
      for (const Mesh& mesh : m.meshes)
        for (uint32_t i : mesh.indices) ASSERT_LT(i, mesh.vertices.size());
      ++loaded;
    } catch (const Error& e) {
      ASSERT_NE(std::string(e.what()).find("fuzz.glb"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(refused, 0);
}

TEST(Gltf, CommittedTestAssetsLoadTheSameAsGlbAndGltf) {
  // tests/engine/scene/data/gltf: one asset as .glb and as .gltf with a base64 data-URI buffer.
  fs::path dir = repo_root() / "tests/engine/scene/data/gltf";
  Model a = load_gltf(dir / "quad.glb"), b = load_gltf(dir / "quad.gltf");
  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(b.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].indices, b.meshes[0].indices);
  ASSERT_EQ(a.meshes[0].vertices.size(), b.meshes[0].vertices.size());
  for (size_t i = 0; i < a.meshes[0].vertices.size(); ++i) {
    EXPECT_EQ(a.meshes[0].vertices[i].position, b.meshes[0].vertices[i].position);
    EXPECT_EQ(a.meshes[0].vertices[i].normal, b.meshes[0].vertices[i].normal);
  }
  EXPECT_FALSE(a.meshes[0].generated_normals);
  EXPECT_EQ(a.textures.at(0).rgba, b.textures.at(0).rgba);
  EXPECT_TRUE(near(a.bounds.min, {10, 0, -2}));
  EXPECT_TRUE(near(b.bounds.max, {12, 0, 0}));
}
