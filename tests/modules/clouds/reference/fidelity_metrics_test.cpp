// The fidelity measures and the EXR files, on the CPU.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "modules/clouds/reference/exr_file.h"
#include "modules/clouds/reference/fidelity_metrics.h"
#include "modules/clouds/render/reference_scene.h"
#include "engine/scene/model.h"
#include "tests/support/temp_dir.h"

namespace cumulo::clouds {
namespace {

namespace fs = std::filesystem;

render::ReferenceImage image(uint32_t w, uint32_t h, glm::vec3 c, float opacity) {
  render::ReferenceImage r;
  r.width = w, r.height = h, r.samples = 16;
  r.radiance.assign(size_t(w) * h, glm::vec4(c, opacity));
  r.luminance_stderr.assign(size_t(w) * h, 0.01f);
  return r;
}

TEST(FidelityError, IsZeroForTheSameImageAndTheRelativeLuminanceDifferenceOtherwise) {
  render::ReferenceImage ref = image(4, 2, glm::vec3(0.5f), 1.0f);
  for (size_t i = 4; i < 8; ++i) ref.radiance[i].a = 0.0f;  // the bottom row is sky
  std::vector<glm::vec4> rt(ref.radiance.begin(), ref.radiance.end());
  FidelityError e = fidelity_error(rt, ref);
  EXPECT_EQ(e.error_mean, 0.0);
  EXPECT_EQ(e.error_in_cloud, 0.0);
  EXPECT_EQ(e.cloud_pixels, 4u);
  for (size_t i = 0; i < 4; ++i) rt[i] = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);  // 20 % brighter in cloud
  for (size_t i = 4; i < 8; ++i) rt[i] = glm::vec4(0.45f, 0.45f, 0.45f, 1.0f);  // 10 % darker outside
  e = fidelity_error(rt, ref);
  EXPECT_NEAR(e.error_in_cloud, 0.2, 1e-5);
  EXPECT_NEAR(e.bias_in_cloud, 0.2, 1e-5);
  EXPECT_NEAR(e.error_mean, 0.15, 1e-5);
  EXPECT_NEAR(e.stderr_in_cloud, 0.02, 1e-5);
  EXPECT_GT(e.noise_in_cloud, 0.0);
  EXPECT_THROW(fidelity_error(std::vector<glm::vec4>(3), ref), Error);
}

TEST(FidelityError, MapsTheErrorToColourInsideTheCloudOnly) {
  render::ReferenceImage ref = image(2, 1, glm::vec3(1.0f), 1.0f);
  ref.radiance[1].a = 0.0f;
  const std::vector<glm::vec4> rt{glm::vec4(1.5f), glm::vec4(1.5f)};
  const gpu::Rgba8Image m = error_map(rt, ref);
  ASSERT_EQ(m.width, 2u);
  EXPECT_GT(m.at(0, 0)[0], 200);  // 50 % error: red
  EXPECT_LT(m.at(0, 0)[2], 60);
  EXPECT_EQ(m.at(1, 0)[0], m.at(1, 0)[2]);  // outside: grey
  gpu::Rgba8Image a{3, 2, std::vector<uint8_t>(24, 255)}, b{1, 2, std::vector<uint8_t>(8, 255)};
  const gpu::Rgba8Image s = side_by_side({&a, &b});
  EXPECT_EQ(s.width, 3u + 2u + 1u);
  EXPECT_EQ(s.height, 2u);
  EXPECT_EQ(s.at(3, 0)[0], 0);  // the gap
}

TEST(ExrFile, RoundTripsLinearFloatsAndRejectsBadFiles) {
  const fs::path dir = test::fresh_temp_dir("cumulo_exr");
  std::vector<glm::vec4> px{{0.0f, 1.0f, 1e4f, 1.0f}, {-1.0f, 0.5f, 3.25f, 0.25f}, {1e-6f, 2.0f, 4.0f, 0.0f}};
  write_exr(dir / "a.exr", 3, 1, px);
  uint32_t w = 0, h = 0;
  EXPECT_EQ(read_exr(dir / "a.exr", &w, &h), px);
  EXPECT_EQ(w, 3u);
  EXPECT_THROW(write_exr(dir / "b.exr", 2, 2, px), Error);  // wrong pixel count
  EXPECT_THROW(read_exr(dir / "missing.exr", &w, &h), Error);
  std::ofstream(dir / "bad.exr") << "not an exr";
  try {
    read_exr(dir / "bad.exr", &w, &h);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.exr"), std::string::npos) << e.what();
  }
  // Truncated: the header without its pixels.
  {
    std::ifstream in(dir / "a.exr", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "cut.exr", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  EXPECT_THROW(read_exr(dir / "cut.exr", &w, &h), Error);
  EXPECT_THROW(write_exr(dir / "no_such_dir" / "c.exr", 3, 1, px), Error);
}

// A 100 x 100 m ramp (y = x / 10) of one material: the heightfield holds its height at texel centres and
// the material's colour.
TEST(TerrainHeightfield, RasterizesTrianglesFromAbove) {
  auto model = std::make_shared<scene::Model>();
  scene::Mesh mesh;
  mesh.vertices = {{{0, 0, 0}, {0, 1, 0}, {0, 0}}, {{100, 10, 0}, {0, 1, 0}, {1, 0}}, {{100, 10, 100}, {0, 1, 0}, {1, 1}},
                   {{0, 0, 100}, {0, 1, 0}, {0, 1}}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.material = 0;
  model->meshes.push_back(mesh);
  scene::Material mat;
  mat.base_color_factor = glm::vec4(0.2f, 0.4f, 0.6f, 1.0f);
  model->materials.push_back(mat);
  model->instances.push_back({0, glm::mat4(1.0f), "ramp"});
  model->bounds.add(glm::vec3(0.0f));
  model->bounds.add(glm::vec3(100.0f, 10.0f, 100.0f));
  cumulo::render::ModelDraw draw{model, glm::translate(glm::mat4(1.0f), glm::vec3(-50.0f, 5.0f, 0.0f))};
  const render::TerrainHeightfield h = render::rasterize_heightfield({draw}, 10);
  ASSERT_EQ(h.resolution, 10u);
  EXPECT_FLOAT_EQ(h.origin.x, -50.0f);
  EXPECT_FLOAT_EQ(h.size.x, 100.0f);
  for (uint32_t i = 0; i < 10; ++i) {
    const glm::vec4 t = h.texels[5 * 10 + i];
    EXPECT_NEAR(t.x, 5.0f + (float(i) + 0.5f), 1e-3f) << i;  // (x + 0.5) * 10 m / 10, lifted 5 m
    EXPECT_NEAR(t.y, 0.2f, 1e-6f);
    EXPECT_NEAR(t.w, 0.6f, 1e-6f);
  }
  EXPECT_NEAR(h.max_height, 14.5f, 1e-3f);
  EXPECT_TRUE(render::rasterize_heightfield({}, 10).empty());
}

}  // namespace
}  // namespace cumulo::clouds
