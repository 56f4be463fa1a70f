// The clouds' shadow on the scene (issue 10): a cloud over the sample terrain darkens the ground where
// the sun's ray through it lands, and nowhere with `--clouds off`, `--cloud-shadows off` or once the
// cloud has dissipated. Headless on lavapipe with validation (run() fails on a validation error).
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/core/file_io.h"
#include "tests/modules/clouds/module/clouds_run_fixture.h"

namespace fs = std::filesystem;
using namespace cumulo;

namespace {

using test::CloudsRun;
using test::Png;
using test::load_png;
using test::luminance;


// The sample terrain from above at 14:00, the test's small cloud (scaled 2x) 1 km up west of the main
// island: its shadow falls on the island's north-west slope.
std::string shadow_level(const std::string& extra_cloud_components) {
  const std::string terrain = fs::absolute("content/levels/sample/terrain.glb").string();
  return R"({"version": 1, "name": "cloud-shadow-test", "entities": [
    {"name": "sun", "components": {"TimeOfDay": {"hours": 14}}},
    {"name": "ground", "components": {"Transform": {"position": [0, 0, 0]}, "ModelRef": {"path": ")" + terrain + R"("}}},
    {"name": "cloud", "components": {"Transform": {"position": [-700, 1000, 350], "scale": [2, 2, 2]},
                                     "Cloudscape": {"asset": "small_cloud.json"})" + extra_cloud_components + R"(}},
    {"name": "cam", "components": {"Transform": {"position": [0, 2600, 300], "look_at": [0, 0, -300]}, "Camera": {}}}]})";
}

struct ShadowStats {
  int pixels = 0;         // ground pixels at least 15 % darker than without the shadow
  double ratio = 1.0;     // their mean luminance ratio (shadowed / unshadowed)
  double cx = 0, cy = 0;  // their centroid
};

// Pixels of `shadowed` darker than `lit` where no cloud is drawn (`lit` equals the cloudless `none`).
ShadowStats shadow_stats(const Png& shadowed, const Png& lit, const Png& none) {
  ShadowStats s;
  double ratio_sum = 0;
  for (int y = 0; y < lit.h; ++y)
    for (int x = 0; x < lit.w; ++x) {
      int cloud = 0;
      for (int c = 0; c < 3; ++c) cloud += std::abs(lit.at(x, y, c) - none.at(x, y, c));
      if (cloud > 3) continue;
      const double a = luminance(shadowed, x, y), b = luminance(lit, x, y);
      if (b < 8.0 || a > 0.85 * b) continue;
      ++s.pixels;
      ratio_sum += a / b;
      s.cx += x, s.cy += y;
    }
  if (s.pixels) s.ratio = ratio_sum / s.pixels, s.cx /= s.pixels, s.cy /= s.pixels;
  return s;
}

}  // namespace

TEST_F(CloudsRun, ACloudShadowsTheTerrainUnderItAndNothingWithoutIt) {
  const fs::path file = dir_ / "shadow.json";
  write_file_atomic(file, shadow_level(""));
  const fs::path dissipating = dir_ / "dissipating.json";
  write_file_atomic(dissipating, shadow_level(R"(, "StormbirdDissipation": {"event": "gone", "duration_s": 0.5})"));
  ASSERT_EQ(run(file, "on.png"), 0);
  ASSERT_EQ(run(file, "no_shadows.png", {"--cloud-shadows", "off"}), 0);
  ASSERT_EQ(run(file, "off.png", {"--clouds", "off"}), 0);
  ASSERT_EQ(run(dissipating, "gone.png", {"--event", "gone@0", "--start-at", "1"}), 0);
  ASSERT_EQ(run(dissipating, "gone_off.png", {"--clouds", "off", "--start-at", "1"}), 0);
  const Png on = load_png(dir_ / "on.png"), no_shadows = load_png(dir_ / "no_shadows.png"), off = load_png(dir_ / "off.png");
  const Png gone = load_png(dir_ / "gone.png"), gone_off = load_png(dir_ / "gone_off.png");
  ASSERT_EQ(on.w, 160);

  const ShadowStats s = shadow_stats(on, no_shadows, off);
  std::printf("  shadow: %d px (%.1f %% of the frame), mean luminance ratio %.2f, centroid (%.0f, %.0f)\n", s.pixels,
              100.0 * s.pixels / (on.w * on.h), s.ratio, s.cx, s.cy);
  // A 400 m cloud from 2.6 km: a patch of tens of pixels, well under half the light left in it.
  EXPECT_GT(s.pixels, 60);
  EXPECT_LT(s.pixels, on.w * on.h / 10);
  EXPECT_LT(s.ratio, 0.7);
  // On the island south-east of the cloud (the afternoon sun is south-west), not on the cloud itself.
  EXPECT_NEAR(s.cx, 80.0, 15.0);
  EXPECT_NEAR(s.cy, 50.0, 15.0);
  // Without the clouds, or with their shadows off, the ground is the cloudless ground.
  EXPECT_EQ(shadow_stats(no_shadows, off, off).pixels, 0);
  EXPECT_EQ(shadow_stats(off, off, off).pixels, 0);
  // A dissipated cloud casts none: its frame is the cloudless one.
  EXPECT_EQ(gone.rgba, gone_off.rgba);
}
