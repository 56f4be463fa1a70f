// The path-traced reference (reference_tracer.h) against analytic solutions, and on the test cloud.
// Small images on lavapipe; every estimate is compared with its known value within a few standard errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "modules/clouds/reference/reference_tracer.h"
#include "tests/modules/clouds/render/cloud_test_util.h"

namespace cumulo::clouds::render::test {
namespace {

constexpr float kPi = 3.14159265f;
float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

class Reference : public CloudRenderFixture {
 protected:
  void SetUp() override {
    CloudRenderFixture::SetUp();
    if (HasFatalFailure()) return;
    tracer_ = std::make_unique<ReferenceTracer>(ctx(), *library_);
  }
  void TearDown() override {
    tracer_.reset();
    CloudRenderFixture::TearDown();
  }

  // Accumulates `frames` frames of the tracer's samples_per_frame and reads the result.
  ReferenceImage trace(const CloudFrameInputs& in, uint32_t frames) {
    using namespace cumulo::render;
    tracer_->reset();
    for (uint32_t f = 0; f < frames; ++f) {
      RenderGraph g({width_, height_});
      const TextureHandle depth = g.import_texture("test.scene_depth", TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, width_, height_),
                                                   depth_.handle(), depth_.view(), ResourceState::shader_read_only());
      TextureHandle hdr = g.create_texture("hdr", TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT));
      CloudLightOutputs light;
      if (!in.instances.empty()) light = add_cloud_light_passes(*res_, g, in);
      hdr = tracer_->add_passes(g, in, light, hdr, depth);
      ctx().submit_and_wait([&](VkCommandBuffer cmd) { executor_->execute(g, cmd); });
    }
    return tracer_->read();
  }

  // A camera at the origin looking down -z, with the sun (when used) toward `sun`.
  CloudFrameInputs analytic_inputs(glm::vec3 sun = {0.6f, 0.0f, 0.8f}) const {
    CloudFrameInputs in;
    scene::Camera cam;
    cam.fov_y_deg = 30.0f;
    in.camera = scene::make_camera_view(scene::Transform::look_at({0, 0, 0}, {0, 0, -1}), cam, float(width_) / float(height_));
    in.sun_direction = glm::normalize(sun);
    in.sun_color = glm::vec3(2.0f);
    return in;
  }
  glm::vec3 ray(const CloudFrameInputs& in, uint32_t x, uint32_t y) const {
    const glm::vec2 ndc((x + 0.5f) / width_ * 2.0f - 1.0f, (y + 0.5f) / height_ * 2.0f - 1.0f);
    return in.camera.ray_direction(ndc);
  }

  std::unique_ptr<ReferenceTracer> tracer_;
};

// A purely absorbing slab 50 m thick in front of a uniform sky of radiance 1, with a majorant twice its
// extinction (null collisions): each pixel is exp(-sigma d / |cos|), the view ray's transmittance too.
TEST_F(Reference, AbsorbingSlabTransmitsBeerLambert) {
  set_size(16, 16);
  const float sigma = 0.02f, d = 50.0f;
  ReferenceSettings& s = tracer_->settings();
  s.sun = false;
  s.analytic = AnalyticMedium{{-1e5f, -1e5f, -100.0f - d}, {1e5f, 1e5f, -100.0f}, sigma, 0.0f, 2.0f * sigma};
  s.uniform_sky = 1.0f;
  s.samples_per_frame = 32;
  const CloudFrameInputs in = analytic_inputs();
  const ReferenceImage img = trace(in, 4);
  ASSERT_EQ(img.samples, 128u);
  double mean_err = 0, mean_view_err = 0;
  int outliers = 0;
  for (uint32_t y = 0; y < height_; ++y)
    for (uint32_t x = 0; x < width_; ++x) {
      const float T = std::exp(-sigma * d / std::fabs(ray(in, x, y).z));
      const glm::vec4 v = img.radiance[y * width_ + x];
      const double se = std::sqrt(T * (1.0 - T) / img.samples);
      if (std::fabs(v.r - T) > 4.5 * se) ++outliers;
      mean_err += v.r - T;
      mean_view_err += (1.0f - v.a) - T;
    }
  const double n = double(width_) * height_;
  EXPECT_LE(outliers, 1);
  EXPECT_NEAR(mean_err / n, 0.0, 0.01);
  EXPECT_NEAR(mean_view_err / n, 0.0, 0.01);
  EXPECT_EQ(img.majorant_violations, 0.0);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// Single scattering (1 bounce, isotropic phase, albedo 0.8) of a sun at 37 degrees from the normal by a
// slab of optical depth 1: L = E w / (4 pi) mu0 / (mu0 + mu) (1 - exp(-tau (1 / mu0 + 1 / mu))).
TEST_F(Reference, SingleScatteringOfAUniformSlabMatchesTheClosedForm) {
  set_size(16, 16);
  const float sigma = 0.01f, d = 100.0f, albedo = 0.8f;
  ReferenceSettings& s = tracer_->settings();
  s.sky = false;
  s.max_bounces = 1;
  s.phase = ReferencePhase::Isotropic;
  s.analytic = AnalyticMedium{{-1e5f, -1e5f, -100.0f - d}, {1e5f, 1e5f, -100.0f}, sigma, albedo, 1.5f * sigma};
  s.samples_per_frame = 32;
  const CloudFrameInputs in = analytic_inputs();
  const ReferenceImage img = trace(in, 4);
  const float mu0 = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f)).z, tau = sigma * d;
  double sum_ref = 0, sum = 0;
  int outliers = 0;
  for (uint32_t y = 0; y < height_; ++y)
    for (uint32_t x = 0; x < width_; ++x) {
      const float mu = std::fabs(ray(in, x, y).z);
      const float L = 2.0f * albedo / (4.0f * kPi) * mu0 / (mu0 + mu) * (1.0f - std::exp(-tau * (1.0f / mu0 + 1.0f / mu)));
      const glm::vec4 v = img.radiance[y * width_ + x];
      const float se = img.luminance_stderr[y * width_ + x];
      if (std::fabs(v.g - L) > 4.5f * se + 1e-4f) ++outliers;
      sum_ref += L;
      sum += v.g;
    }
  EXPECT_LE(outliers, 2);
  EXPECT_NEAR(sum / sum_ref, 1.0, 0.02);
  EXPECT_EQ(img.majorant_violations, 0.0);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// The white furnace: a non-absorbing cube (optical depth 2 across) under a uniform sky of radiance 1
// neither gains nor loses energy, whatever the phase function: every pixel is 1.
TEST_F(Reference, NonAbsorbingMediumInAUniformSkyConservesEnergy) {
  set_size(16, 16);
  for (ReferencePhase phase : {ReferencePhase::Cloud, ReferencePhase::Mie, ReferencePhase::Isotropic}) {
    SCOPED_TRACE(reference_phase_name(phase));
    ReferenceSettings& s = tracer_->settings();
    s.sun = false;
    s.max_bounces = 512;
    s.phase = phase;
    s.analytic = AnalyticMedium{{-100.0f, -100.0f, -400.0f}, {100.0f, 100.0f, -200.0f}, 0.01f, 1.0f, 0.012f};
    s.uniform_sky = 1.0f;
    s.samples_per_frame = 16;
    CloudFrameInputs in = analytic_inputs();
    in.settings.hg_forward = 0.8f, in.settings.hg_backward = -0.3f, in.settings.hg_forward_weight = 0.7f;
    const ReferenceImage img = trace(in, 2);
    double sum = 0, lo = 1e9, hi = -1e9, opacity = 0, var = 0;
    for (size_t i = 0; i < img.radiance.size(); ++i) {
      const glm::vec4 v = img.radiance[i];
      var += double(img.luminance_stderr[i]) * img.luminance_stderr[i];
      sum += v.g;
      lo = std::min<double>(lo, v.g), hi = std::max<double>(hi, v.g);
      opacity = std::max<double>(opacity, v.a);
    }
    EXPECT_GT(opacity, 0.5);  // the cube fills the view's centre
    // Within 4 standard errors of the image mean (the Mie weights make it noisy) and 1 %.
    const double n = double(img.radiance.size());
    const double se = std::sqrt(var) / n;
    EXPECT_LT(se, 0.01);
    EXPECT_NEAR(sum / n, 1.0, 4.0 * se + 0.002);
    if (phase != ReferencePhase::Mie) {  // weight 1 per bounce: exactly 1 unless a path is cut at 512
      EXPECT_GT(lo, 0.97);
      EXPECT_LT(hi, 1.03);
    }
  }
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

// The same seed gives the same picture; another seed a different one.
TEST_F(Reference, IsDeterministicForASeed) {
  set_size(8, 8);
  ReferenceSettings& s = tracer_->settings();
  s.sun = true;
  s.analytic = AnalyticMedium{{-100.0f, -100.0f, -400.0f}, {100.0f, 100.0f, -200.0f}, 0.01f, 0.9f, 0.02f};
  s.uniform_sky = 0.5f;
  s.samples_per_frame = 4;
  const ReferenceImage a = trace(analytic_inputs(), 2), b = trace(analytic_inputs(), 2);
  s.seed = 7;
  const ReferenceImage c = trace(analytic_inputs(), 2);
  EXPECT_EQ(0, std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(glm::vec4)));
  EXPECT_NE(0, std::memcmp(a.radiance.data(), c.radiance.data(), a.radiance.size() * sizeof(glm::vec4)));
}

// On the test cloud: the majorant grid bounds the up-rez density everywhere the paths went, the cloud is
// where the sphere projects, and its brightness is that of the real-time march within a loose factor.
TEST_F(Reference, TracesTheTestCloudUnderItsMajorantsAndNearTheRealTimeMarch) {
  set_size(40, 24);
  CloudFrameInputs in = inputs(asset(), camera());
  ReferenceSettings& s = tracer_->settings();
  s.max_bounces = 16;
  s.samples_per_frame = 8;
  s.analytic.reset();
  s.uniform_sky = luminance(in.ambient_color);  // the real-time ambient is the sky's mean radiance
  const ReferenceImage img = trace(in, 2);
  EXPECT_EQ(img.majorant_violations, 0.0);
  const glm::vec4 centre = img.radiance[(height_ / 2) * width_ + width_ / 2];
  EXPECT_GT(centre.a, 0.8f);                    // the sphere's centre is opaque
  EXPECT_LT(img.radiance[0].a, 0.05f);          // the corner sees past it
  const Frame rt = render(in);
  const float rt_centre = luminance(glm::vec3(rt.at(width_ / 2, height_ / 2)));
  const float ref_centre = luminance(glm::vec3(centre));
  std::printf("test cloud centre: reference %.3f, real-time %.3f\n", ref_centre, rt_centre);
  EXPECT_GT(ref_centre, 0.5f * rt_centre);
  EXPECT_LT(ref_centre, 2.0f * rt_centre);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

}  // namespace
}  // namespace cumulo::clouds::render::test

namespace cumulo::clouds::render::test {
namespace {

// An asset whose voxel counts are not multiples of the majorant cell (51 x 26 x 51 at 10 m): the last cell
// per axis reaches past the box, and the bound still holds everywhere the paths sample.
TEST_F(Reference, TheMajorantGridBoundsAnAssetOfAnySize) {
  std::string recipe = kTestRecipe;
  recipe.replace(recipe.find("\"voxel_size\": 8"), 15, "\"voxel_size\": 10");
  bake::Recipe r = bake::parse_recipe_text(recipe, "odd.json", test_data().root);
  bake::BakeSettings settings;
  settings.show_progress = false;
  const fs::path dir = test_data().root / "odd_cloudscape";
  bake::write_bake_outputs(r, bake::bake_recipe(r, settings), dir);
  const auto odd = asset({}, dir);
  ASSERT_NE(odd->modeling_image().extent().width % 8, 0u);
  set_size(32, 18);
  CloudFrameInputs in = inputs(odd, camera());
  ReferenceSettings& s = tracer_->settings();
  s.max_bounces = 8;
  s.samples_per_frame = 8;
  s.uniform_sky = 0.5f;
  const ReferenceImage img = trace(in, 1);
  EXPECT_EQ(img.majorant_violations, 0.0);
  EXPECT_GT(img.radiance[(height_ / 2) * width_ + width_ / 2].a, 0.8f);
  EXPECT_EQ(ctx().validation_errors(), 0u);
}

}  // namespace
}  // namespace cumulo::clouds::render::test
