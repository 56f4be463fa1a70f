// The clouds' shadow on the scene and their light shafts (issue 10): a cloud over the sample terrain darkens the ground where
// the sun's ray through it lands, and nowhere with `--clouds off`, `--cloud-shadows off` or once the
// cloud has dissipated. Headless on lavapipe with validation (run() fails on a validation error).
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/core/file_io.h"
#include "engine/scene/components.h"
#include "engine/scene/gltf.h"
#include "engine/scene/sun.h"
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

// Light shafts (2017 talk): with the sun straight behind the test cloud, the sky around the cloud loses
// some of its Mie glow (the shadowed air), and with the cloud beside the sun almost nothing changes.
TEST_F(CloudsRun, LightShaftsDarkenTheHazeBehindACloudInFrontOfTheSun) {
  // 17:00: the sun toward (-0.953, 0.301, 0.01); the camera 900 m from the cloud's centre, away from the sun.
  auto write_level = [&](const std::string& name, const std::string& cloud_position) {
    const fs::path file = dir_ / (name + ".json");
    write_file_atomic(file, R"({"version": 1, "name": "shafts", "entities": [
      {"name": "sun", "components": {"TimeOfDay": {"hours": 17}}},
      {"name": "cloud", "components": {"Transform": {"position": )" + cloud_position + R"(}, "Cloudscape": {"asset": "small_cloud.json"}}},
      {"name": "cam", "components": {"Transform": {"position": [858, 357, -9], "look_at": [0, 628, 0]}, "Camera": {}}}]})");
    return file;
  };
  const fs::path behind = write_level("behind", "[0, 500, 0]"), beside = write_level("beside", "[0, 500, 700]");
  ASSERT_EQ(run(behind, "on.png", {}, 8), 0);
  ASSERT_EQ(run(behind, "off.png", {"--cloud-light-shafts", "off"}, 8), 0);
  ASSERT_EQ(run(beside, "beside_on.png", {}, 8), 0);
  ASSERT_EQ(run(beside, "beside_off.png", {"--cloud-light-shafts", "off"}, 8), 0);
  const Png on = load_png(dir_ / "on.png"), off = load_png(dir_ / "off.png");
  const Png beside_on = load_png(dir_ / "beside_on.png"), beside_off = load_png(dir_ / "beside_off.png");
  // The sky within 30 px of the view's centre (the sun), where the cloud itself is not (same in both runs
  // of the beside level, which has no cloud there).
  auto ratio = [&](const Png& a, const Png& b) {
    double sa = 0, sb = 0;
    for (int y = 0; y < a.h; ++y)
      for (int x = 0; x < a.w; ++x) {
        const double r = std::hypot(x + 0.5 - a.w / 2.0, y + 0.5 - a.h / 2.0);
        if (r < 30.0) sa += luminance(a, x, y), sb += luminance(b, x, y);
      }
    return sa / sb;
  };
  const double behind_ratio = ratio(on, off), beside_ratio = ratio(beside_on, beside_off);
  std::printf("  luminance within 30 px of the sun, shafts on / off: cloud in front %.3f, cloud beside %.3f\n",
              behind_ratio, beside_ratio);
  EXPECT_LT(behind_ratio, 0.98);
  EXPECT_GT(beside_ratio, 0.995);
}

// With the sun off screen the shafts' samples toward it leave the picture: there they take the border's value, fading
// to open sky. Taken as open sky at once, the sample level's immersed view (sun off to the upper left) had a straight
// lighter strip down its ocean along the left border, the shafts' darkening ramping from 1.0 at the border to 0.79 by
// 12 px (160x90); now it is even across the border.
TEST_F(CloudsRun, LightShaftsStayEvenAtTheBorderOfTheScreenWithTheSunOffIt) {
  const fs::path sample = "content/levels/sample/level.json";
  ASSERT_EQ(run(sample, "on.png", {"--camera", "immersed"}, 8), 0);
  ASSERT_EQ(run(sample, "off.png", {"--camera", "immersed", "--cloud-light-shafts", "off"}, 8), 0);
  const Png on = load_png(dir_ / "on.png"), off = load_png(dir_ / "off.png");
  // The shafts' darkening (on / off) over the open ocean at the left border: its spread across the first 16 columns.
  double spread = 0, darkening = 0;
  int rows = 0;
  for (int y = 64; y < 80; ++y, ++rows) {  // below the horizon, between two small clouds at the border
    double lo = 1e9, hi = -1e9;
    for (int x = 0; x < 16; ++x) {
      const double r = luminance(on, x, y) / std::max(1.0, luminance(off, x, y));
      lo = std::min(lo, r), hi = std::max(hi, r);
      darkening += 1.0 - r;
    }
    spread += hi - lo;
  }
  spread /= rows;
  darkening /= rows * 16.0;
  std::printf("  immersed, ocean at the left border: the shafts' darkening %.3f, its spread across 16 px %.3f\n", darkening, spread);
  EXPECT_GT(darkening, 0.05);  // the shafts do shade that air (cloud toward the sun)
  EXPECT_LT(spread, 0.08);
}

// The terrain's shadow on the clouds (issue 10: "the sun behind a mountain darkens the cloud base near
// it"): the test cloud just behind the main island's peak from a 17:36 sun, its sun ray through the
// mountain, is darker than with --cloud-terrain-shadow off; lifted above the peak's shadow, the same.
TEST_F(CloudsRun, TheSunBehindAMountainDarkensTheCloudBehindIt) {
  const fs::path terrain = fs::absolute("content/levels/sample/terrain.glb");
  const scene::Model model = scene::load_gltf(terrain);
  glm::vec3 peak(0.0f, -1e9f, 0.0f);
  for (const scene::MeshInstance& inst : model.instances)
    for (const scene::Vertex& v : model.meshes[inst.mesh].vertices) {
      const glm::vec3 p = glm::vec3(inst.world * glm::vec4(v.position, 1.0f));
      if (p.y > peak.y) peak = p;
    }
  scene::TimeOfDay tod;
  tod.hours = 17.6f;
  const glm::vec3 l = scene::sun_direction(tod);
  // 700 m behind the peak along the light, its light ray 60 m below the summit where it passes it.
  const glm::vec3 centre = peak - l * 700.0f - glm::vec3(0.0f, 60.0f, 0.0f);
  const glm::vec3 side = glm::normalize(glm::cross(l, glm::vec3(0, 1, 0)));
  auto write_level = [&](const std::string& name, float lift) {
    const glm::vec3 c = centre + glm::vec3(0.0f, lift, 0.0f);
    const glm::vec3 cam = c + side * 700.0f - glm::vec3(0.0f, 120.0f, 0.0f);
    auto v3 = [](glm::vec3 v) { return "[" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + "]"; };
    const fs::path file = dir_ / (name + ".json");
    write_file_atomic(file, R"({"version": 1, "name": "terrain-shadow", "entities": [
      {"name": "sun", "components": {"TimeOfDay": {"hours": 17.6}}},
      {"name": "ground", "components": {"Transform": {"position": [0, 0, 0]}, "ModelRef": {"path": ")" + terrain.string() + R"("}}},
      {"name": "cloud", "components": {"Transform": {"position": )" + v3(c - glm::vec3(0, 128, 0)) + R"(}, "Cloudscape": {"asset": "small_cloud.json"}}},
      {"name": "cam", "components": {"Transform": {"position": )" + v3(cam) + R"(, "look_at": )" + v3(c) + R"(}, "Camera": {}}}]})");
    return file;
  };
  // Mean luminance where the cloud is (its pixels differ from the frame without clouds), shadow on / off.
  auto ratio = [&](const fs::path& level, const std::string& name) {
    EXPECT_EQ(run(level, name + "_on.png", {}, 6), 0);
    EXPECT_EQ(run(level, name + "_off.png", {"--cloud-terrain-shadow", "off"}, 6), 0);
    EXPECT_EQ(run(level, name + "_none.png", {"--clouds", "off"}, 6), 0);
    const Png on = load_png(dir_ / (name + "_on.png")), off = load_png(dir_ / (name + "_off.png"));
    const Png none = load_png(dir_ / (name + "_none.png"));
    double a = 0, b = 0;
    int n = 0;
    for (int y = 0; y < on.h; ++y)
      for (int x = 0; x < on.w; ++x) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d += std::abs(off.at(x, y, c) - none.at(x, y, c));
        if (d <= 12) continue;
        a += luminance(on, x, y), b += luminance(off, x, y), ++n;
      }
    EXPECT_GT(n, 100) << name;
    return n ? a / b : 1.0;
  };
  const double behind = ratio(write_level("behind", 0.0f), "behind");
  const double above = ratio(write_level("above", 700.0f), "above");
  std::printf("  peak (%.0f, %.0f, %.0f); cloud luminance, terrain shadow on / off: behind the peak %.3f, lifted 700 m %.3f\n",
              peak.x, peak.y, peak.z, behind, above);
  EXPECT_LT(behind, 0.98);  // a low sun: its direct light is a small part of the cloud's (ambient, multiple scattering)
  EXPECT_GT(above, 0.995);
}
