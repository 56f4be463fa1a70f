// FrameRenderer on the default device (lavapipe on CI) with validation on: the engine's frame
// (geometry, sky, tonemap) renders with zero validation errors, empty depth shows the atmosphere only, the
// sample terrain shows below the horizon, and the compiled graph has the three passes.
#include "engine/render/frame_renderer.h"

#include <gtest/gtest.h>

#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/gpu/readback.h"
#include "engine/render/sky_model.h"
#include "engine/scene/camera.h"
#include "engine/scene/gltf.h"
#include "engine/scene/sun.h"
#include "tests/support/render_offscreen.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

struct FrameRendererTest : ::testing::Test {
  gpu::Context ctx{[] {
    gpu::ContextDesc d;
    d.validation = true;
    return d;
  }()};
  static constexpr uint32_t kW = 160, kH = 90;
  double frame_ms = 0.0;  // CPU time of the last render(): record, submit, wait for the GPU, read back

  FrameSnapshot snapshot(glm::vec3 pos, glm::vec3 target, float hours) {
    FrameSnapshot s;
    s.width = kW;
    s.height = kH;
    scene::Camera cam;
    s.camera = scene::make_camera_view(scene::Transform::look_at(pos, target), cam, float(kW) / kH);
    scene::TimeOfDay tod;
    tod.hours = hours;
    s.sun = scene::sun_light(tod, scene::Sun{});
    s.lighting = sky_lighting(s.sun);
    return s;
  }

  gpu::Rgba8Image render(FrameRenderer& r, const FrameSnapshot& s) {
    Stopwatch frame_clock;
    gpu::Rgba8Image img = test::render_offscreen(ctx, r, s);
    frame_ms = frame_clock.ms();
    return img;
  }
};

double luminance_rows(const gpu::Rgba8Image& img, uint32_t y0, uint32_t y1, int channel = -1) {
  double sum = 0;
  for (uint32_t y = y0; y < y1; ++y)
    for (uint32_t x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        if (channel < 0 || channel == c) sum += img.at(x, y)[c];
  return sum / double((y1 - y0) * img.width * (channel < 0 ? 3 : 1));
}

}  // namespace

TEST_F(FrameRendererTest, EmptySceneIsSkyBlueAboveAndSunlitGroundBelow) {
  FrameRenderer r(ctx);
  auto img = render(r, snapshot({0, 10, 0}, {0, 10, -100}, 12.0f));  // level view at noon
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  // Top rows: blue sky (blue clearly above red).
  EXPECT_GT(luminance_rows(img, 0, 10, 2), luminance_rows(img, 0, 10, 0) + 20.0);
  // Below the horizon (no geometry): the atmosphere's sunlit ground (albedo 0.3), warmer than the sky above
  // the horizon (less blue for its red).
  const double ground_b = luminance_rows(img, 80, 90, 2), ground_r = luminance_rows(img, 80, 90, 0);
  const double sky_b = luminance_rows(img, 30, 44, 2), sky_r = luminance_rows(img, 30, 44, 0);
  EXPECT_LT(ground_b / std::max(ground_r, 1.0), sky_b / std::max(sky_r, 1.0));
  // The graph: geometry, sky, tonemap, in that order; on the first frame the atmosphere's LUTs before the sky.
  const CompiledGraph& g = r.last_compiled();
  EXPECT_LT(g.position("geometry"), g.position("sky"));
  EXPECT_LT(g.position("sky"), g.position("tonemap"));
  EXPECT_LT(g.position("atmosphere.transmittance"), g.position("atmosphere.multiscatter"));
  EXPECT_LT(g.position("atmosphere.multiscatter"), g.position("atmosphere.sky_view"));
  EXPECT_LT(g.position("atmosphere.sky_view"), g.position("sky"));
  EXPECT_LT(g.position("atmosphere.aerial_perspective"), g.position("geometry"));  // the terrain's haze
  // GPU timings: each pass clears or shades every pixel, so it takes measurable time, and together
  // they fit inside the CPU time from recording to the end of the wait.
  ASSERT_TRUE(ctx.info().timestamps) << "the test device has no timestamps";
  auto t = r.pass_timings();
  ASSERT_EQ(t.size(), 7u);  // geometry, the three LUTs and the aerial froxels, sky, tonemap
  double sum_ms = 0.0;
  for (auto& [name, ms] : t) {
    EXPECT_GT(ms, 0.0) << name;
    sum_ms += ms;
  }
  EXPECT_LT(sum_ms, frame_ms);
}

TEST_F(FrameRendererTest, SampleTerrainCoversTheLowerHalf) {
  auto model = std::make_shared<const scene::Model>(scene::load_gltf("content/levels/sample/terrain.glb"));
  FrameRenderer r(ctx);
  FrameSnapshot s = snapshot({900, 420, 1600}, {-100, 360, -200}, 16.5f);  // the sample level's "mixed" view
  s.models.push_back({model, glm::mat4(1.0f)});
  auto with = render(r, s);
  s.models.clear();
  auto without = render(r, s);
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  // Sky rows are the same with or without the terrain; the lower rows change (islands and ocean).
  EXPECT_NEAR(luminance_rows(with, 0, 10), luminance_rows(without, 0, 10), 2.0);
  double diff = 0;
  for (uint32_t y = 60; y < kH; ++y)
    for (uint32_t x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c) diff += std::abs(int(with.at(x, y)[c]) - int(without.at(x, y)[c]));
  EXPECT_GT(diff / (30.0 * kW * 3), 10.0);
}

TEST_F(FrameRendererTest, NightIsDarkerThanNoon) {
  FrameRenderer r(ctx);
  auto noon = render(r, snapshot({0, 10, 0}, {0, 60, -100}, 12.0f));
  auto night = render(r, snapshot({0, 10, 0}, {0, 60, -100}, 0.0f));
  EXPECT_GT(luminance_rows(noon, 0, kH), 3.0 * luminance_rows(night, 0, kH));
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
}

// A point light (a lightning discharge's foot) lights the terrain near it and leaves the sky alone; lights
// past FRAME_MAX_POINT_LIGHTS are dropped, not written past the block.
TEST_F(FrameRendererTest, PointLightLightsTheTerrainAtNight) {
  auto model = std::make_shared<const scene::Model>(scene::load_gltf("content/levels/sample/terrain.glb"));
  FrameRenderer r(ctx);
  FrameSnapshot s = snapshot({900, 420, 1600}, {-100, 360, -200}, 23.0f);
  s.models.push_back({model, glm::mat4(1.0f)});
  auto dark = render(r, s);
  for (int i = 0; i < 6; ++i) s.lighting.point_lights.push_back({{500, 200, 900}, 3000.0f, glm::vec3(0.5f)});
  EXPECT_EQ(make_frame_params(s, 1.0f).point_light_count.x, uint32_t(FRAME_MAX_POINT_LIGHTS));
  auto lit = render(r, s);
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  const double below_dark = luminance_rows(dark, 60, kH), below_lit = luminance_rows(lit, 60, kH);
  std::printf("  terrain rows at night: %.2f dark, %.2f lit\n", below_dark, below_lit);
  EXPECT_GT(below_lit, below_dark * 1.5 + 2.0);
  EXPECT_NEAR(luminance_rows(lit, 0, 10), luminance_rows(dark, 0, 10), 1.0);  // the sky rows
}

// The sky pass draws the atmosphere's sky-view LUT: looking toward a setting sun the band above the horizon
// is redder than the sky higher up; the night sky is darker than the twilight one by at least 3x even
// through the exposure meter; no validation errors.
TEST_F(FrameRendererTest, AtmosphereSkyAtSunsetTwilightAndNight) {
  FrameRenderer r(ctx);
  auto shot = [&](float elevation_deg) {
    FrameSnapshot s = snapshot({0, 10, 0}, {0, 10 + 46.6f, -100}, 12.0f);  // 25 degrees up, toward -z
    const float e = glm::radians(elevation_deg);
    s.sun.direction = glm::vec3(0.0f, std::sin(e), -std::cos(e));
    s.sun.elevation_deg = elevation_deg;
    s.lighting = sky_lighting(s.sun, 10.0f);
    return render(r, s);
  };
  const auto sunset = shot(3.0f), twilight = shot(-3.0f), night = shot(-25.0f);
  EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  auto ratio = [&](const gpu::Rgba8Image& img, uint32_t y0, uint32_t y1) {
    return luminance_rows(img, y0, y1, 0) / std::max(luminance_rows(img, y0, y1, 2), 1.0);
  };
  // The horizon sits 25 degrees below the centre: row ~ 45 + 25/30 x 45 = 82 of 90.
  const double horizon = ratio(sunset, 70, 80), high = ratio(sunset, 0, 10);
  std::printf("  sunset red/blue: %.2f above the horizon, %.2f high up\n", horizon, high);
  EXPECT_GT(horizon, 1.3 * high);
  const double lt = luminance_rows(twilight, 0, 80), ln = luminance_rows(night, 0, 80);
  std::printf("  sky (8-bit mean): twilight %.1f, night %.1f\n", lt, ln);
  EXPECT_GT(lt, 3.0 * ln);
  EXPECT_GT(ln, 0.0);
}

TEST(SkyModel, FrameParamsCarryCameraAndSun) {
  FrameSnapshot s;
  s.width = 320;
  s.height = 180;
  s.sun.direction = glm::normalize(glm::vec3(0.3f, 0.8f, -0.2f));
  s.sun.elevation_deg = 50.0f;
  s.lighting = sky_lighting(s.sun);
  s.sim_time = 2.5;
  shared::FrameParams p = make_frame_params(s, 1.5f);
  EXPECT_FLOAT_EQ(p.viewport_size.x, 320.0f);
  EXPECT_FLOAT_EQ(p.inv_viewport_size.y, 1.0f / 180.0f);
  EXPECT_FLOAT_EQ(p.time_s, 2.5f);
  EXPECT_FLOAT_EQ(p.exposure, 1.5f);
  EXPECT_NEAR(glm::length(p.sun_direction), 1.0f, 1e-5f);
  // The sun radiance and ambient come from the snapshot's lighting (a module may replace it).
  EXPECT_FLOAT_EQ(p.sun_radiance.r, s.lighting.sun_radiance.r);
  EXPECT_FLOAT_EQ(p.ambient, s.lighting.ambient);
  s.lighting.sun_radiance = glm::vec3(7.0f);
  s.lighting.ambient = 0.25f;
  EXPECT_FLOAT_EQ(make_frame_params(s).sun_radiance.g, 7.0f);
  EXPECT_FLOAT_EQ(make_frame_params(s).ambient, 0.25f);
  // Day sky: zenith bluer than red; night sky far darker than day.
  EXPECT_GT(p.sky_zenith.z, p.sky_zenith.x);
  scene::SunLight night;
  night.elevation_deg = -30.0f;
  night.direction = glm::vec3(0.0f, -0.5f, 0.8660254f);
  EXPECT_LT(sky_lighting(night).sky_zenith.z, 0.1f * sky_lighting(s.sun).sky_zenith.z);
}
