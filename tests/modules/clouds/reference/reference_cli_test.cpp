// `cumulo reference` and `cumulo fidelity` through the real executable, at tiny sizes and few samples: they
// run clean, write what the issue names (EXR + PNG; the JSON with its views, errors and images) and reject
// bad input with a message that names it. Their numbers are for people to read, never asserted here.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "modules/clouds/reference/exr_file.h"
#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using cumulo::test::run_cumulo;

namespace {
std::string sample_level() { return (fs::path(CUMULO_SOURCE_DIR) / "content/levels/sample/level.json").string(); }
}  // namespace

TEST(ReferenceCli, WritesADeterministicExrAndAPngBesideIt) {
  const fs::path dir = cumulo::test::fresh_temp_dir("cumulo_reference_cli");
  const std::string args = "reference " + sample_level() + " --camera mixed --size 32x18 --spp 2 --max-bounces 4 -o ";
  auto r = run_cumulo(args + (dir / "a.exr").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2/2 spp (100 %)"), std::string::npos) << r.output;  // progress with an ETA
  EXPECT_NE(r.output.find("ETA"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("standard error of the luminance"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "a.png"));
  ASSERT_EQ(run_cumulo(args + (dir / "b.exr").string()).exit_code, 0);
  uint32_t w = 0, h = 0, w2 = 0, h2 = 0;
  const auto a = cumulo::clouds::read_exr(dir / "a.exr", &w, &h);
  const auto b = cumulo::clouds::read_exr(dir / "b.exr", &w2, &h2);
  ASSERT_EQ(w, 32u);
  ASSERT_EQ(h, 18u);
  ASSERT_EQ(a.size(), b.size());
  double sum = 0, alpha_max = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], b[i]) << "pixel " << i;  // the same seed: the same image
    sum += a[i].g;
    EXPECT_GE(a[i].a, -1e-3f);
    EXPECT_LE(a[i].a, 1.0f + 1e-3f);
    alpha_max = std::max<double>(alpha_max, a[i].a);
  }
  EXPECT_GT(sum, 0.0);
  EXPECT_GT(alpha_max, 0.2);  // the mixed view sees clouds (alpha: their opacity)
}

TEST(ReferenceCli, RejectsBadArgumentsNamingThem) {
  auto r = run_cumulo("reference " + sample_level() + " --spp 0 -o /tmp/x.exr");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--spp"), std::string::npos) << r.output;
  r = run_cumulo("reference " + sample_level() + " --phase rayleigh -o /tmp/x.exr");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--phase"), std::string::npos) << r.output;
  r = run_cumulo("reference " + sample_level());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("-o OUT.exr"), std::string::npos) << r.output;
  r = run_cumulo("reference " + sample_level() + " --camera nowhere --size 16x16 --spp 1 -o /tmp/x.exr");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("nowhere"), std::string::npos) << r.output;
  // A folder that cannot be written: the message names the file.
  r = run_cumulo("reference " + sample_level() + " --size 16x16 --spp 1 -o /nonexistent_dir/x.exr");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("/nonexistent_dir/x.exr"), std::string::npos) << r.output;
}

TEST(FidelityCli, WritesTheJsonTheImagesAndTheTable) {
  const fs::path dir = cumulo::test::fresh_temp_dir("cumulo_fidelity_cli");
  {
    std::ofstream v(dir / "views.json");
    v << R"({"views": [
      {"name": "mixed", "camera": "mixed"},
      {"name": "edges", "camera": "mixed", "sun": "viewer", "target": [-650, 820, -850], "distance": 1600, "height": 450,
       "fov_y_deg": 50, "effect": "dark-edges"}]})";
  }
  const fs::path out = dir / "fidelity.json";
  auto r = run_cumulo("fidelity " + sample_level() + " --views-file " + (dir / "views.json").string() +
                      " --size 32x18 --spp 2 --max-bounces 4 --frames 2 --warmup 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| view | effect | error (all) |"), std::string::npos) << r.output;
  std::ifstream f(out);
  const auto j = nlohmann::json::parse(f);
  EXPECT_FALSE(j["device"]["name"].get<std::string>().empty());
  EXPECT_EQ(j["settings"]["spp"], 2);
  EXPECT_EQ(j["settings"]["constants"], nlohmann::json::array({"slab", "talk"}));
  // The lighting is measured at the talk's light grid on every device unless --cloud-light-grid device asks otherwise.
  EXPECT_EQ(j["settings"]["light_grid"], nlohmann::json::array({256, 256, 32}));
  ASSERT_EQ(j["views"].size(), 2u);
  for (const auto& v : j["views"]) {
    for (const char* key : {"name", "error_mean", "error_in_cloud", "error_in_cloud_noise_corrected", "spp", "images", "constants"})
      EXPECT_TRUE(v.contains(key)) << key;
    for (const char* key : {"belly_lower_third", "rim_core_ratio", "band_pass_contrast"})
      EXPECT_TRUE(v["constants"]["slab"].contains(key)) << key;
    EXPECT_GE(v["error_mean"].get<double>(), 0.0);
    EXPECT_EQ(v["spp"], 2);
    for (const char* image : {"realtime", "reference", "error", "side_by_side", "reference_exr"})
      EXPECT_TRUE(fs::exists(out.parent_path() / v["images"][image].get<std::string>())) << image;
  }
  EXPECT_EQ(j["views"][1]["effect"]["name"], "dark-edges");
  EXPECT_TRUE(j["views"][1]["effect"].contains("error_in_cloud_without"));
  EXPECT_TRUE(fs::exists(out.parent_path() / j["views"][1]["images"]["realtime_without_effect"].get<std::string>()));
}

// One light alone (--cloud-lights): the reference is traced with the same one, and a reference traced with other
// lights is not reused.
TEST(FidelityCli, TracesTheReferenceWithTheLightsTheRealTimeImageHas) {
  const fs::path dir = cumulo::test::fresh_temp_dir("cumulo_fidelity_lights");
  {
    std::ofstream v(dir / "views.json");
    v << R"({"views": [{"name": "mixed", "camera": "mixed"}]})";
  }
  auto run = [&](const std::string& lights, const std::string& out, const std::string& extra = "") {
    auto r = run_cumulo("fidelity " + sample_level() + " --views-file " + (dir / "views.json").string() +
                        " --size 32x18 --spp 2 --max-bounces 4 --frames 2 --warmup 1 --constants slab --reuse-references --images " +
                        (dir / "images").string() + " --cloud-lights " + lights + " --out " + (dir / out).string() + extra);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::ifstream f(dir / out);
    return nlohmann::json::parse(f);
  };
  const auto sun = run("sun", "sun.json", " --cloud-light-grid device");
  EXPECT_EQ(sun["settings"]["lights"], "sun");
  // The device's own grid when asked for: on a CPU device (lavapipe) the smaller one.
  if (sun["device"]["name"].get<std::string>().find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(sun["settings"]["light_grid"], nlohmann::json::array({96, 96, 16}));
  }
  EXPECT_GT(sun["views"][0]["constants"]["slab"]["opaque_pixels"].get<int>(), 0);
  const auto all = run("all", "all.json");
  EXPECT_FALSE(all["views"][0]["reference_reused"].get<bool>()) << "traced with the sun alone: not the reference of all the lights";
  EXPECT_GT(all["views"][0]["reference_luminance_in_cloud"].get<double>(), sun["views"][0]["reference_luminance_in_cloud"].get<double>());
  EXPECT_GT(all["views"][0]["realtime_luminance_in_cloud"].get<double>(), sun["views"][0]["realtime_luminance_in_cloud"].get<double>());
  EXPECT_TRUE(run("all", "again.json")["views"][0]["reference_reused"].get<bool>());
}

TEST(FidelityCli, ABadViewsFileIsReportedWithItsPlace) {
  const fs::path dir = cumulo::test::fresh_temp_dir("cumulo_fidelity_bad");
  auto write = [&](const char* text) {
    std::ofstream(dir / "views.json") << text;
    return run_cumulo("fidelity " + sample_level() + " --views-file " + (dir / "views.json").string() +
                      " --size 16x16 --spp 1 --frames 1 --out " + (dir / "f.json").string());
  };
  auto r = write(R"({"views": [{"name": "a", "camera": "mixed", "effect": "god-rays"}]})");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("views.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("god-rays"), std::string::npos) << r.output;
  r = write(R"({"views": [{"name": "a"}]})");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("$.views[0]"), std::string::npos) << r.output;
  r = write(R"({"views": [{"name": "a", "camera": "mixed",)");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("views.json:1:"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "f.json"));
}
