// The fidelity measures and the EXR files, on the CPU.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "modules/clouds/reference/exr_file.h"
#include "modules/clouds/reference/fidelity_features.h"
#include "modules/clouds/reference/fidelity_metrics.h"
#include "modules/clouds/reference/reference_scene.h"
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

// The opaque pixels' error (a run with one light alone is read there): the thin pixels, where the background
// shows, are left out.
TEST(FidelityError, MeasuresTheOpaquePixelsApart) {
  render::ReferenceImage ref = image(4, 1, glm::vec3(0.5f), 1.0f);
  ref.radiance[2].a = ref.radiance[3].a = 0.5f;  // thin: the background shows through
  std::vector<glm::vec4> rt(ref.radiance.begin(), ref.radiance.end());
  rt[0] = rt[1] = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);  // 20 % brighter where opaque
  rt[2] = rt[3] = glm::vec4(1.0f, 1.0f, 1.0f, 1.0f);  // twice as bright where thin
  const FidelityError e = fidelity_error(rt, ref);
  EXPECT_EQ(e.opaque_pixels, 2u);
  EXPECT_EQ(e.cloud_pixels, 4u);
  EXPECT_NEAR(e.bias_opaque, 0.2, 1e-5);
  EXPECT_NEAR(e.error_opaque_corrected, std::sqrt(0.1 * 0.1 - 0.01 * 0.01) / 0.5, 1e-5);
  EXPECT_NEAR(e.bias_in_cloud, 0.6, 1e-5);
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

// The noise-corrected error: a real-time image equal to the reference's truth, measured against a noisy
// reference, reads the noise as error in the plain metric and mostly not in the corrected one; a true 20 %
// difference far above the noise reads about 20 % in both.
TEST(FidelityError, TakesTheReferencesNoiseOutOfTheCorrectedError) {
  const uint32_t w = 64, h = 64;
  render::ReferenceImage ref = image(w, h, glm::vec3(1.0f), 1.0f);
  std::vector<glm::vec4> truth(ref.radiance.begin(), ref.radiance.end());
  uint32_t state = 12345u;
  auto gauss = [&] {  // Box-Muller on a small LCG
    auto u = [&] { state = state * 1664525u + 1013904223u; return (double(state >> 8) + 0.5) / double(1u << 24); };
    return std::sqrt(-2.0 * std::log(u())) * std::cos(6.283185307179586 * u());
  };
  const float se = 0.1f;
  for (size_t i = 0; i < ref.radiance.size(); ++i) {
    ref.radiance[i] = glm::vec4(glm::vec3(1.0f + se * float(gauss())), 1.0f);
    ref.luminance_stderr[i] = se;
  }
  FidelityError e = fidelity_error(truth, ref);
  EXPECT_NEAR(e.error_in_cloud, 0.08, 0.01);  // E|N(0, 0.1)| = 0.08
  EXPECT_LT(e.error_in_cloud_corrected, 0.045);  // the estimator's floor is 0.34 se
  for (glm::vec4& v : truth) v = glm::vec4(1.2f, 1.2f, 1.2f, 1.0f);
  e = fidelity_error(truth, ref);
  EXPECT_NEAR(e.error_in_cloud_corrected, 0.2, 0.02);
}

// A disc of opacity 1 on a transparent image: the largest silhouette finds it and not a smaller blob; its
// lower third, rim and core are where they should be; a flat image has no band-pass contrast and a checker
// has much, and noise of a known standard error is taken out of it.
TEST(FidelityFeatures, MeasureTheBellyTheRimAndTheStructure) {
  const uint32_t w = 64, h = 48;
  render::ReferenceImage ref = image(w, h, glm::vec3(0.0f), 0.0f);
  std::vector<float> lum(size_t(w) * h, 0.0f);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const float dx = float(x) - 24.0f, dy = float(y) - 24.0f;
      const size_t i = size_t(y) * w + x;
      if (dx * dx + dy * dy <= 16.0f * 16.0f) {
        ref.radiance[i].a = 1.0f;
        lum[i] = y >= 30 ? 0.25f : 1.0f;  // a dark belly
      }
      if (x >= 58 && y < 3) ref.radiance[i].a = 1.0f;  // a small blob elsewhere
    }
  const std::vector<uint8_t> body = largest_silhouette(ref, 0.5f);
  EXPECT_EQ(body[size_t(24) * w + 24], 1);
  EXPECT_EQ(body[size_t(1) * w + 60], 0);
  EXPECT_NEAR(lower_third_mean(lum, body, w, h), 0.25, 1e-6);  // rows 8..40: the lower third is from row 29.3 down
  const std::vector<uint16_t> d = inside_distance(body, w, h, false);
  EXPECT_EQ(d[size_t(24) * w + 8], 1);   // the disc's left edge
  EXPECT_EQ(d[size_t(24) * w + 24], 17);  // its centre
  std::vector<float> rimmed(lum.size(), 1.0f);
  for (size_t i = 0; i < d.size(); ++i)
    if (d[i] > 0 && d[i] <= 2) rimmed[i] = 3.0f;
  EXPECT_NEAR(rim_core_ratio(rimmed, body, w, h), 3.0, 1e-6);
  EXPECT_NEAR(band_pass_contrast(std::vector<float>(lum.size(), 0.5f), w, h), 0.0, 1e-6);
  std::vector<float> checker(lum.size());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) checker[size_t(y) * w + x] = ((x / 4 + y / 4) % 2) ? 1.0f : 0.2f;
  const double c = band_pass_contrast(checker, w, h);
  EXPECT_GT(c, 0.1);
  std::vector<float> noisy = checker;
  uint32_t state = 7u;
  for (float& v : noisy) {
    state = state * 1664525u + 1013904223u;
    v += 1.0f * (float(state >> 8) / float(1u << 24) - 0.5f) * 3.4641f;  // uniform, standard deviation 1
  }
  const double raw = band_pass_contrast(noisy, w, h), corrected = band_pass_contrast(noisy, w, h, std::vector<float>(noisy.size(), 1.0f));
  std::printf("  band-pass contrast: clean %.4f, noisy %.4f, noise taken out %.4f\n", c, raw, corrected);
  EXPECT_GT(raw, c * 1.1) << "noise reads as structure";
  EXPECT_LT(std::fabs(corrected - c), std::fabs(raw - c)) << "and is mostly taken out";
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
