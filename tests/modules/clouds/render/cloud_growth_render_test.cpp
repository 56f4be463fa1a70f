// A cloud grown during play (issue 26) through the whole renderer (FrameRenderer + CloudFeature) on lavapipe with
// validation and synchronization validation, 64x36: the frame's CloudGrowthFrame drives the runtime
// (cloud_growth_runtime.h), which steps the solver on the GPU and draws its images.
//   - TheCloudBuildsAsItSteps: no cloud at the first step; after 20 steps (10 a frame) cloud pixels where there were
//     none, the steps taken as the frames asked, before the light grid (rebuilt) in the frame's graph;
//   - AHeldCloudGivesTheSameFrame: with the target reached, two frames at a still camera give the same bytes and the
//     solver's and the images' bytes do not change (no step, no update);
//   - ANewGenerationStartsAgain: a new generation takes the simulation back to its first step;
//   - TheMarchHasNoHolesWhereTheFieldChanges: a step a frame at a still camera; no pixel loses the cloud for a frame.
// The spec: a mediocris thermal on 16x12x16 cells of 24 game m (GrowGpu's) in moist air with 30 s steps, so cloud
// forms by step 10-20 (~100 cells of 3072 above the iso at step 15 on the CPU).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/readback.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/sky_model.h"
#include "engine/scene/camera.h"
#include "engine/scene/sun.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/grow_gpu/grown_asset_gpu.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/scene/density_query.h"
#include "modules/clouds/volume/volume.h"
#include "tests/engine/gpu/gpu_test_util.h"
#include "tests/support/render_offscreen.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
using namespace cumulo::clouds;
using namespace cumulo::clouds::render;

namespace {

namespace fs = std::filesystem;

const char* kSpec = R"({"preset": "mediocris", "seed": 3, "grid": {"cells": [16, 12, 16], "cell": 24},
  "time": {"steps": 80, "dt": 30}, "atmosphere": {"humidity": [0.95, 0.9]}})";
constexpr uint64_t kKey = 7;
constexpr uint32_t kWidth = 64, kHeight = 36;

class CloudGrowthRender : public gpu::test::GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    if (HasFatalFailure()) return;
    dir_ = cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_growth_render"));
    spec_ = dir_ / "growth.json";
    std::ofstream(spec_) << kSpec;
    CloudRenderOptions& o = feature_.options();
    o.noise_size = 32;
    o.temporal = false;    // each frame whole: two frames of the same state are the same picture
    o.talk_jitter = true;  // a static jitter beyond 250 m (the cloud is 500 m away and more)
    o.light_shafts = false;
    o.rain = false;
    feature_.on_level_loaded(true, false);
    renderer_ = std::make_unique<cumulo::render::FrameRenderer>(ctx());
    renderer_->add_feature(feature_);
  }
  void TearDown() override {
    renderer_.reset();  // waits for the device and destroys the feature's GPU objects
    GpuTest::TearDown();
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // One frame of the growing cloud at `target` steps and `generation`, from a still camera 700 m away.
  gpu::Rgba8Image frame(int target, uint32_t generation = 0) {
    cumulo::render::FrameSnapshot s;
    s.width = kWidth;
    s.height = kHeight;
    scene::TimeOfDay tod;
    tod.hours = 11.0f;
    s.sun = scene::sun_light(tod, scene::Sun{});
    s.lighting = cumulo::render::sky_lighting(s.sun);
    s.camera = scene::make_camera_view(scene::Transform::look_at({0, 160, 700}, {0, 160, 0}), scene::Camera{},
                                       float(kWidth) / float(kHeight));
    s.camera_name = "test";
    s.frame_index = ++frame_index_;  // as the engine's frames (the light grid's sweep goes by it)
    CloudFrame cf;
    CloudInstanceFrame inst;
    inst.folder = dir_;  // not loaded: the growing cloud draws its own images
    inst.growth = CloudGrowthFrame{spec_, kKey, target, generation};
    cf.instances.push_back(inst);
    s.extensions.set(std::move(cf));
    const auto t0 = std::chrono::steady_clock::now();
    gpu::Rgba8Image img = cumulo::test::render_offscreen(ctx(), *renderer_, s);
    last_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return img;
  }
  double pass_ms(const std::string& name) const {
    for (const auto& [n, ms] : renderer_->pass_timings())
      if (n == name) return ms;
    return -1.0;
  }
  // Held frames (the target reached) until one rebuilds or sweeps no level of the light grid; how many it took.
  int settle(int target, uint32_t generation = 0) {
    const int most = 2 * int(CloudResourcesDesc::for_device(ctx().info()).light_grid_divisions) + 4;
    for (int f = 1; f <= most; ++f) {
      frame(target, generation);
      if (pass_ms("clouds.light_grid") < 0.0) return f;
    }
    ADD_FAILURE() << "the light grid still worked after " << most << " held frames";
    return most;
  }
  const CloudGrowthRuntime& runtime() const {
    const CloudGrowthRuntime* r = feature_.growth_runtime(kKey);
    if (!r) throw std::runtime_error("no growth runtime");
    return *r;
  }
  // The largest difference of a pixel's colour channels between two images.
  static int pixel_diff(const gpu::Rgba8Image& a, const gpu::Rgba8Image& b, size_t i) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.pixels[4 * i + c]) - int(b.pixels[4 * i + c])));
    return d;
  }
  static size_t changed_pixels(const gpu::Rgba8Image& a, const gpu::Rgba8Image& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size() / 4; ++i) n += pixel_diff(a, b, i) > 4;
    return n;
  }

  fs::path dir_, spec_;
  CloudFeature feature_;
  std::unique_ptr<cumulo::render::FrameRenderer> renderer_;
  double last_ms_ = 0.0;
  uint64_t frame_index_ = 0;
};

size_t cells_above(const std::vector<float>& qc, float iso) {
  size_t n = 0;
  for (float q : qc) n += q > iso;
  return n;
}

TEST_F(CloudGrowthRender, TheCloudBuildsAsItSteps) {
  feature_.options().growth_steps_per_frame = 10;
  feature_.options().growth_spread = false;  // the steps and their images in one frame
  const gpu::Rgba8Image start = frame(0);
  EXPECT_EQ(runtime().steps_done(), 0);
  EXPECT_EQ(runtime().grown().updates_recorded(), 0);  // a start with no cloud: no images made, none drawn
  EXPECT_TRUE(runtime().images_cloudless());
  EXPECT_EQ(cells_above(runtime().solver().read(grow_gpu::Field::CloudWater), runtime().spec().iso), 0u);
  frame(20);
  EXPECT_EQ(runtime().steps_done(), 10);  // at most 10 a frame
  // The steps and the images' update come before anything samples the images (the light grid, rebuilt: it changed).
  std::vector<std::string> order;
  for (const cumulo::render::CompiledPass& p : renderer_->last_compiled().passes) order.push_back(p.name);
  auto at = [&](const std::string& name) { return std::find(order.begin(), order.end(), name) - order.begin(); };
  ASSERT_LT(at(kGrowAssetPass), ptrdiff_t(order.size()));
  EXPECT_LT(at(kGrowPass), at(kGrowAssetPass));
  EXPECT_LT(at(kGrowAssetPass), at("clouds.light_grid"));
  std::printf("growth: 10 steps %.1f ms, the images' update %.1f ms, the light grid %.1f ms (frame %.0f ms wall)\n",
              pass_ms(kGrowPass), pass_ms(kGrowAssetPass), pass_ms("clouds.light_grid"), last_ms_);
  const gpu::Rgba8Image grown = frame(20);
  EXPECT_EQ(runtime().steps_done(), 20);
  EXPECT_EQ(runtime().grown().updates_recorded(), 2);
  const size_t cells = cells_above(runtime().solver().read(grow_gpu::Field::CloudWater), runtime().spec().iso);
  EXPECT_GT(cells, 20u);
  if (const char* dir = std::getenv("CUMULO_CLOUD_TEST_IMAGES"); dir && *dir) {  // for a person to look at
    fs::create_directories(dir);
    gpu::write_png(fs::path(dir) / "growth_step0.png", start);
    gpu::write_png(fs::path(dir) / "growth_step20.png", grown);
  }
  const size_t changed = changed_pixels(start, grown);
  std::printf("growth: %zu cells above the iso at step 20, %zu of %u pixels changed from step 0\n", cells, changed,
              kWidth * kHeight);
  EXPECT_GT(changed, 20u);
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

TEST_F(CloudGrowthRender, AHeldCloudGivesTheSameFrame) {
  feature_.options().growth_steps_per_frame = 8;
  feature_.options().growth_spread = false;  // the steps and their images in one frame
  frame(16);
  frame(16);
  ASSERT_EQ(runtime().steps_done(), 16);
  settle(16);                           // the light grid's sweep of the last images done
  const gpu::Rgba8Image a = frame(16);  // held: no step, no update (the light grid rests)
  const std::vector<float> qc = runtime().solver().read(grow_gpu::Field::CloudWater);
  const std::vector<float> u = runtime().solver().read(grow_gpu::Field::U);
  const std::vector<uint8_t> modeling = runtime().grown().read_modeling();
  const std::vector<uint16_t> field = runtime().grown().read_field();
  const int updates = runtime().grown().updates_recorded();
  const gpu::Rgba8Image b = frame(16);
  EXPECT_EQ(runtime().steps_done(), 16);
  EXPECT_EQ(runtime().grown().updates_recorded(), updates);
  EXPECT_TRUE(a.pixels == b.pixels) << changed_pixels(a, b) << " pixels differ";
  EXPECT_TRUE(qc == runtime().solver().read(grow_gpu::Field::CloudWater));
  EXPECT_TRUE(u == runtime().solver().read(grow_gpu::Field::U));
  EXPECT_TRUE(modeling == runtime().grown().read_modeling());
  EXPECT_TRUE(field == runtime().grown().read_field());
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

TEST_F(CloudGrowthRender, ANewGenerationStartsAgain) {
  feature_.options().growth_steps_per_frame = 3;
  feature_.options().growth_spread = false;  // the steps and their images in one frame
  frame(6);
  frame(6);
  ASSERT_EQ(runtime().steps_done(), 6);
  frame(6, 1);  // reset: back to the first step, then (the target still 6) up to 3 steps again
  EXPECT_EQ(runtime().restarts(), 1);
  EXPECT_EQ(runtime().generation(), 1u);
  EXPECT_EQ(runtime().steps_done(), 3);
  frame(0, 2);  // reset and held at the first step
  EXPECT_EQ(runtime().restarts(), 2);
  EXPECT_EQ(runtime().steps_done(), 0);
  EXPECT_EQ(cells_above(runtime().solver().read(grow_gpu::Field::CloudWater), runtime().spec().iso), 0u);
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

// The CPU density query sees the growing cloud: the modeling image copied for the host with each update, taken when
// its frame slot comes round again (a frame later), byte-equal to the GPU's; its densest voxel has density.
TEST_F(CloudGrowthRender, TheHostSeesTheGrownCloudAFrameLater) {
  feature_.options().growth_steps_per_frame = 10;
  feature_.options().growth_update_frames = 1;
  for (int f = 0; f < 4; ++f) frame(20);  // steps, images, steps, images
  ASSERT_EQ(runtime().steps_done(), 20);
  EXPECT_LT(runtime().modeling_readback_step(), 20);  // the last update's copy is not taken yet
  frame(20);                                           // held: its slot's last copy is complete
  ASSERT_NE(runtime().modeling_readback(), nullptr);
  EXPECT_EQ(runtime().modeling_readback_step(), 20);
  const Volume& m = *runtime().modeling_readback();
  const std::vector<uint8_t> gpu_bytes = runtime().grown().read_modeling();
  EXPECT_TRUE(m.levels[0] == gpu_bytes) << "the host's copy differs from the modeling image";
  size_t best = 0;
  for (size_t i = 0; i < gpu_bytes.size() / 4; ++i)
    if (gpu_bytes[4 * i] * gpu_bytes[4 * i + 2] > gpu_bytes[4 * best] * gpu_bytes[4 * best + 2]) best = i;
  ASSERT_GT(gpu_bytes[4 * best], 0) << "no cloud in the modeling image";
  Volume noise = Volume::create({4, 4, 4}, 1.0f, VolumeEncoding::RGBA8,
                                {{"r", "noise"}, {"g", "noise"}, {"b", "noise"}, {"a", "noise"}});
  std::fill(noise.levels[0].begin(), noise.levels[0].end(), uint8_t(128));
  const CloudDensityQuery q(m, noise);
  const glm::uvec3 d = m.size;
  const glm::uvec3 v(uint32_t(best % d.x), uint32_t(best / d.x % d.y), uint32_t(best / (size_t(d.x) * d.y)));
  const glm::vec3 at = m.bounds_min + (glm::vec3(v) + 0.5f) * m.voxel_size;
  CloudPlacement placement;
  EXPECT_GT(q.density(placement, at, 0.0), 0.0f) << "no density at the densest voxel (" << at.x << ", " << at.y << ", " << at.z << ")";
  EXPECT_EQ(q.density(placement, m.bounds_max + glm::vec3(100.0f), 0.0), 0.0f);
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

// Spread (the default): a frame steps or updates the images (and rebuilds the light grid), never both; a cloud
// that must catch up alternates.
TEST_F(CloudGrowthRender, StepsAndImagesTakeTurns) {
  feature_.options().growth_steps_per_frame = 4;
  feature_.options().growth_update_frames = 1;  // the update whole in the frame after the steps
  frame(0);
  EXPECT_EQ(runtime().steps_done(), 0);
  EXPECT_EQ(runtime().grown().updates_recorded(), 0);  // a start with no cloud: no images to make
  struct Seen {
    int steps, updates;
  };
  std::vector<Seen> seen;
  for (int f = 0; f < 5; ++f) {
    frame(8);
    seen.push_back({runtime().steps_done(), runtime().grown().updates_recorded()});
  }
  const Seen expected[] = {{4, 0}, {4, 1}, {8, 1}, {8, 2}, {8, 2}};
  for (size_t f = 0; f < seen.size(); ++f) {
    EXPECT_EQ(seen[f].steps, expected[f].steps) << "frame " << f + 1;
    EXPECT_EQ(seen[f].updates, expected[f].updates) << "frame " << f + 1;
  }
  // The asset's revision follows its images (the path tracer rebuilds its majorant grid from it).
  EXPECT_EQ(runtime().asset()->revision, uint64_t(runtime().grown().updates_recorded()));
  // The images of the spread frames are those of the same steps in one frame.
  const std::vector<uint8_t> spread = runtime().grown().read_modeling();
  feature_.options().growth_spread = false;
  frame(8, 1);  // a new generation: back to the first step, 4 steps and the images in this frame
  frame(8, 1);
  ASSERT_EQ(runtime().steps_done(), 8);
  EXPECT_TRUE(spread == runtime().grown().read_modeling());
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

// The update spread over frames (the default, --cloud-growth-update-frames 4): after a frame that steps, three frames
// of the distance field's and attributes' passes that leave the images and the picture as they were (no step
// meanwhile), then the images and the light grid; the same bytes as the update whole in one frame.
TEST_F(CloudGrowthRender, AnUpdateSpreadOverFramesChangesThePictureOnlyInItsLast) {
  feature_.options().growth_steps_per_frame = 24;
  feature_.options().growth_update_frames = 1;
  frame(24);
  frame(24);  // 24 steps, then their images whole
  ASSERT_EQ(runtime().steps_done(), 24);
  ASSERT_FALSE(runtime().images_cloudless());
  settle(24);
  const gpu::Rgba8Image before = frame(24);  // held
  const std::vector<uint8_t> modeling_before = runtime().grown().read_modeling();

  feature_.options().growth_steps_per_frame = 4;
  feature_.options().growth_update_frames = 4;
  frame(28);  // 4 steps
  EXPECT_EQ(runtime().steps_done(), 28);
  const int updates = runtime().grown().updates_recorded(), stages = runtime().grown().stages_recorded();
  for (int f = 0; f < 3; ++f) {
    const gpu::Rgba8Image during = frame(32);  // the target moved on: still no step while the update runs
    EXPECT_EQ(runtime().steps_done(), 28) << "update frame " << f;
    EXPECT_TRUE(runtime().updating()) << "update frame " << f;
    EXPECT_GT(runtime().grown().stages_recorded(), stages) << "update frame " << f;
    EXPECT_EQ(runtime().grown().updates_recorded(), updates) << "update frame " << f;
    EXPECT_EQ(pass_ms("clouds.light_grid"), -1.0) << "the light grid was rebuilt in update frame " << f;
    EXPECT_TRUE(during.pixels == before.pixels) << changed_pixels(during, before) << " pixels changed in update frame " << f;
    EXPECT_TRUE(runtime().grown().read_modeling() == modeling_before) << "the images changed in update frame " << f;
  }
  const gpu::Rgba8Image after = frame(32);  // the images and the light grid
  EXPECT_GT(pass_ms("clouds.light_grid"), 0.0);
  EXPECT_FALSE(runtime().updating());
  EXPECT_EQ(runtime().grown().updates_recorded(), updates + 1);
  EXPECT_EQ(runtime().asset()->revision, uint64_t(runtime().grown().updates_recorded()));
  EXPECT_GT(changed_pixels(after, before), 0u) << "4 more steps changed no pixel";
  const std::vector<uint8_t> spread = runtime().grown().read_modeling();
  frame(32);
  EXPECT_EQ(runtime().steps_done(), 32) << "the next step waited for more than the update";

  // The same 28 steps with the update in one frame: the same images.
  feature_.options().growth_spread = false;
  feature_.options().growth_steps_per_frame = 28;
  frame(28, 1);
  frame(28, 1);
  ASSERT_EQ(runtime().steps_done(), 28);
  EXPECT_TRUE(spread == runtime().grown().read_modeling());
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

// The light grid follows new images by the sweep's cycle (--cloud-growth-light-sweep on) instead of a
// rebuild: a level or so a frame from the one nearest the sun, done within a cycle of frames (16 on a CPU device),
// and then the picture is the one a rebuild gives. New images while a cycle is under way let it finish and add one.
TEST_F(CloudGrowthRender, TheLightGridSweepsNewImagesInWithinACycle) {
  const int divisions = int(CloudResourcesDesc::for_device(ctx().info()).light_grid_divisions);
  feature_.options().growth_light_sweep = true;
  feature_.options().growth_spread = false;  // the steps and their images in one frame
  feature_.options().growth_steps_per_frame = 24;
  frame(24);  // the first images: the grid is built whole
  settle(24);
  feature_.options().growth_steps_per_frame = 4;
  frame(28);  // 4 steps and their images: the sweep's cycle starts
  EXPECT_GT(pass_ms("clouds.light_grid"), 0.0);
  const int swept = settle(28);
  std::printf("growth: the light grid swept the new images in over %d frames (a cycle: %d)\n", swept, divisions);
  EXPECT_EQ(swept, divisions) << "a cycle is " << divisions << " frames after the one that changed the images";
  const gpu::Rgba8Image sweep = frame(28);

  // New images half-way through a cycle: it finishes and one whole cycle follows.
  frame(32);
  for (int f = 0; f < divisions / 2; ++f) frame(32);
  frame(36);
  EXPECT_EQ(settle(36), divisions - divisions / 2 - 1 + divisions) << "the cycle under way and one more";

  // The same steps with a rebuild: the same picture.
  feature_.options().growth_light_sweep = false;
  feature_.options().growth_steps_per_frame = 24;
  frame(24, 1);
  settle(24, 1);
  feature_.options().growth_steps_per_frame = 4;
  frame(28, 1);
  EXPECT_GT(pass_ms("clouds.light_grid"), 0.0);
  EXPECT_EQ(settle(28, 1), 1) << "a rebuilt grid is current in the next frame";
  const gpu::Rgba8Image rebuilt = frame(28, 1);
  size_t differ = 0;
  int most = 0;
  for (size_t i = 0; i < sweep.pixels.size() / 4; ++i) {
    differ += pixel_diff(sweep, rebuilt, i) > 0;
    most = std::max(most, pixel_diff(sweep, rebuilt, i));
  }
  std::printf("growth: swept against rebuilt: %zu pixels differ, by %d levels at most\n", differ, most);
  EXPECT_LE(most, 1) << "the swept light grid gives another picture than the rebuilt one";
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

// Issue 26's "no holes where the field changes": a step and its images every frame at a still camera (temporal off,
// a static jitter, so only the field changes the picture). A hole is a pixel that shows cloud in the frames before
// and after and (nearly) none in the one between: what a stale or non-conservative SDF over the new density, or
// images half updated, would draw. The metric is printed with the cloud's growth over the frames.
TEST_F(CloudGrowthRender, TheMarchHasNoHolesWhereTheFieldChanges) {
  feature_.options().growth_spread = false;
  feature_.options().growth_steps_per_frame = 24;
  const gpu::Rgba8Image sky = frame(0);  // the start state: no cloud, left out of the march
  EXPECT_TRUE(runtime().images_cloudless());
  frame(24);
  EXPECT_FALSE(runtime().images_cloudless());
  feature_.options().growth_steps_per_frame = 1;
  std::vector<gpu::Rgba8Image> frames;
  for (int step = 25; step <= 48; ++step) frames.push_back(frame(step));
  ASSERT_EQ(runtime().steps_done(), 48);
  const size_t pixels = size_t(kWidth) * kHeight;
  auto cloud = [&](const gpu::Rgba8Image& img, size_t i) { return pixel_diff(img, sky, i); };  // from the cloudless sky
  auto covered = [&](const gpu::Rgba8Image& img) {
    size_t n = 0;
    for (size_t i = 0; i < pixels; ++i) n += cloud(img, i) >= 24;
    return n;
  };
  size_t holes = 0, changed = 0;
  for (size_t k = 1; k + 1 < frames.size(); ++k)
    for (size_t i = 0; i < pixels; ++i) {
      const int around = std::min(cloud(frames[k - 1], i), cloud(frames[k + 1], i)), here = cloud(frames[k], i);
      holes += around >= 24 && 4 * here < around;
      changed += pixel_diff(frames[k - 1], frames[k], i) > 4;
    }
  const size_t first = covered(frames.front()), last = covered(frames.back());
  std::printf("growth, steps 25-48 a step a frame: cloud pixels %zu -> %zu of %zu, %.1f pixels changed a frame, %zu holes\n",
              first, last, pixels, double(changed) / double(frames.size() - 2), holes);
  EXPECT_GT(first, 10u);
  EXPECT_GT(last, first + 20);  // it grew: the metric saw the field change
  EXPECT_GT(changed, 0u);
  EXPECT_EQ(holes, 0u);
  EXPECT_EQ(ctx().validation_errors(), 0u) << ctx().last_validation_message();
}

}  // namespace
