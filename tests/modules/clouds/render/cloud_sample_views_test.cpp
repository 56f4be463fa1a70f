// The baked sample cloudscape from the sample level's three cameras, at 320x180, in every ablation and
// in the 30 Hz (one march) and 60 Hz (split) modes: per-pass GPU ms (median of the frames after a warm-up
// frame), steps per pixel, and PNGs when CUMULO_CLOUD_TEST_IMAGES is set. A measurement for people, not
// a pass/fail test: it runs only when CUMULO_CLOUD_SAMPLE names a folder holding `cloudscape/` (cumulo
// bake content/levels/sample/cloudscape.json) and `noise/voxel_noise.nvdf` (cumulo noise), e.g.
//   export CUMULO_CLOUD_SAMPLE=build/content/sample   # scripts/bake-content.sh writes it
//   build/tests/modules/clouds/render/cumulo_clouds_render_tests --gtest_filter='CloudSampleViews.*'
// The scene is the sky colour with no terrain (the engine wiring adds the terrain's depth).
// CUMULO_CLOUD_SAMPLE_ONLY=word,word... keeps the runs whose "sun view ablation mode" line holds every word
// (e.g. "noon,ground,30"); CUMULO_CLOUD_SAMPLE_FRAMES=N measured frames per run (default 3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "tests/modules/clouds/render/cloud_test_util.h"

using namespace cumulo;
using namespace cumulo::clouds;
using namespace cumulo::clouds::render;
using namespace cumulo::clouds::render::test;

namespace {

class CloudSampleViews : public CloudRenderFixture {
 protected:
  void SetUp() override {
    gpu::test::GpuTest::SetUp();
    if (HasFatalFailure()) return;
    const char* dir = std::getenv("CUMULO_CLOUD_SAMPLE");
    if (!dir || !*dir) GTEST_SKIP() << "set CUMULO_CLOUD_SAMPLE to a folder with cloudscape/ and noise/";
    sample_ = dir;
    library_ = std::make_unique<gpu::PipelineLibrary>(ctx());
    assets_ = std::make_unique<CloudAssetCache>(ctx());
    res_ = create_cloud_resources(ctx(), *library_, assets_->noise(sample_ / "noise/voxel_noise.nvdf"),
                                  CloudResourcesDesc::for_device(ctx().info()));
    executor_ = std::make_unique<cumulo::render::Executor>(ctx());
    set_size(320, 180);
  }
  fs::path sample_;
};

struct View {
  const char* name;
  glm::vec3 position, look_at;
};
// content/levels/sample/level.json, plus "in-hero": inside the hero cumulus (the talk's flight case,
// where the near segment holds the expensive samples and the 40/60 Hz split pays off).
const View kViews[] = {{"ground", {292, 3, -288}, {-552, 469, -824}},
                       {"mixed", {900, 420, 1600}, {-100, 360, -200}},
                       {"immersed", {-300, 900, 400}, {-1300, 930, -500}},
                       {"in-hero", {-650, 780, -560}, {-650, 760, -1400}}};

bool selected(const std::string& run) {
  const char* only = std::getenv("CUMULO_CLOUD_SAMPLE_ONLY");
  if (!only || !*only) return true;
  std::string words = only;
  for (size_t a = 0; a <= words.size();) {
    size_t b = words.find(',', a);
    if (b == std::string::npos) b = words.size();
    if (b > a && run.find(words.substr(a, b - a)) == std::string::npos) return false;
    a = b + 1;
  }
  return true;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1.0 : v[v.size() / 2];
}

TEST_F(CloudSampleViews, CamerasAblationsAndModes) {
  const auto formats = default_cloud_formats(ctx().info());
  auto sky = assets_->cloudscape(sample_ / "cloudscape", formats);
  std::printf("device %s, formats %s, cloudscape %.2f MB + noise, persistent %s\n", ctx().info().name.c_str(),
              formats.bc1_field ? "compressed" : "uncompressed", double(sky->gpu_bytes) / 1e6, "(after the first frame)");
  struct Sun {
    const char* name;
    glm::vec3 dir, color, ambient;
  };
  const Sun suns[] = {{"noon", glm::normalize(glm::vec3(0.15f, 0.95f, 0.25f)), {6.0f, 5.8f, 5.4f}, {0.35f, 0.45f, 0.6f}},
                      {"evening", glm::normalize(glm::vec3(-0.75f, 0.22f, 0.3f)), {5.0f, 3.3f, 2.0f}, {0.25f, 0.28f, 0.38f}}};
  for (const Sun& sun : suns)
    for (const View& v : kViews) {
      scene::Camera cam;
      cam.fov_y_deg = 60.0f;
      const scene::CameraView view =
          scene::make_camera_view(scene::Transform::look_at(v.position, v.look_at), cam, float(width_) / float(height_));
      // Variants of one view are interleaved frame by frame, so a load spike on this shared machine
      // hits all of them alike and the ratios stay fair; medians over the frames after a warm-up.
      struct Run {
        CloudAblation ab;
        int mode;
        std::vector<double> march, grid, total;
        double steps = 0;
        Frame last;
      };
      std::vector<Run> runs;
      for (CloudAblation ab : {CloudAblation::Base, CloudAblation::VoxelLighting, CloudAblation::Full})
        for (int mode : {30, 60}) {
          // The cost table's ablations at 30 Hz and noon; every view in both modes for the full method.
          if ((sun.name != std::string("noon") || mode == 60) && ab != CloudAblation::Full) continue;
          if (!selected(std::string(sun.name) + " " + v.name + " " + ablation_name(ab) + " " + std::to_string(mode))) continue;
          runs.push_back({ab, mode});
        }
      const int frames = std::max(2, std::atoi(std::getenv("CUMULO_CLOUD_SAMPLE_FRAMES") ? std::getenv("CUMULO_CLOUD_SAMPLE_FRAMES") : "3"));
      for (int k = 0; k < frames + 1; ++k)
        for (Run& run : runs) {
          CloudFrameInputs in = inputs(sky, view);
          in.sun_direction = sun.dir, in.sun_color = sun.color, in.ambient_color = sun.ambient;
          in.settings.ablation = run.ab;
          apply_budget_mode(in.settings, run.mode);
          in.settings.temporal = true;
          in.settings.animated_jitter_distance_m = 250.0f;
          in.frame_index = k;
          run.last = render(in);
          run.steps = run.last.mean_steps();
          if (k == 0) continue;  // pipeline JIT, full light-grid rebuild
          const double m = run.mode == 60 ? pass_ms("clouds.march_near") + pass_ms("clouds.march_far") +
                                                pass_ms("clouds.split_merge")
                                          : pass_ms("clouds.march");
          const double g = pass_ms("clouds.light_grid");
          run.march.push_back(m), run.grid.push_back(g);
          run.total.push_back(m + g + pass_ms("clouds.temporal") + pass_ms("clouds.composite"));
        }
      for (Run& run : runs) {
        std::printf("  %-7s %-8s %-14s %d Hz: clouds %7.2f ms (march %7.2f, light grid %6.2f), steps/px %5.1f\n", sun.name,
                    v.name, ablation_name(run.ab), run.mode, median(run.total), median(run.march), median(run.grid), run.steps);
        if (run.ab == CloudAblation::Full)
          maybe_write_png(std::string("sample_") + v.name + "_" + sun.name + "_" + std::to_string(run.mode), width_, height_,
                          run.last.hdr);
      }
    }
  std::printf("persistent cloud memory (light grid + history): %.2f MB\n", double(persistent_gpu_bytes(*res_)) / 1e6);
}

}  // namespace
