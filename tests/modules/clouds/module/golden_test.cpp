// Golden images of the sample level's three cameras with the clouds (160x90, 30 Hz mode, 4 frames of
// temporal accumulation, seed 1, noon), headless on lavapipe with validation. Metric: PSNR of the 8-bit
// RGB screenshot against the committed PNG, at least kMinPsnr dB (the margin covers llvmpipe's code paths
// on other CPUs, not a change of the picture: a visible change of the clouds drops it far below). After an
// intended change of the renderer, regenerate with CUMULO_UPDATE_GOLDEN=1 and look at the new images.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/app/application.h"
#include "modules/clouds/clouds_module.h"
#include "tests/support/png_read.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;

namespace {

constexpr double kMinPsnr = 34.0;
const fs::path kGoldenDir = "tests/modules/clouds/module/golden";

double psnr(const test::Png& a, const test::Png& b) {
  double se = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    const double d = double(a.rgba[i]) - double(b.rgba[i]);
    se += d * d;
    ++n;
  }
  const double mse = se / double(n);
  return mse <= 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

class CloudGolden : public ::testing::TestWithParam<const char*> {};

}  // namespace

TEST_P(CloudGolden, SampleCameraMatchesItsGoldenImage) {
  const std::string camera = GetParam();
  fs::path dir = test::unique_temp_path("cumulo_cloud_golden_" + camera);
  fs::create_directories(dir);
  fs::path shot = dir / (camera + ".png");
  std::vector<std::string> args{"run", "content/levels/sample/level.json", "--headless", "--frames", "4", "--size", "160x90",
                                "--camera", camera, "--time-of-day", "12", "--screenshot", shot.string()};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  app::Modules modules{clouds::make_clouds_module()};
  auto o = app::parse_run_options(int(argv.size()), argv.data(), modules);
  ASSERT_TRUE(o);
  ASSERT_EQ(app::run_level(*o, modules), 0);  // 3: validation errors
  const fs::path golden = kGoldenDir / (camera + ".png");
  if (const char* u = std::getenv("CUMULO_UPDATE_GOLDEN"); u && std::string(u) == "1") {
    fs::create_directories(kGoldenDir);
    fs::copy_file(shot, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " missing: run with CUMULO_UPDATE_GOLDEN=1";
  test::Png got = test::load_png(shot), want = test::load_png(golden);
  ASSERT_EQ(got.w, want.w);
  ASSERT_EQ(got.h, want.h);
  const double p = psnr(got, want);
  EXPECT_GE(p, kMinPsnr) << camera << ": " << p << " dB against " << golden << " (new image: " << shot << ")";
  if (p >= kMinPsnr) fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(SampleLevel, CloudGolden, ::testing::Values("ground", "mixed", "immersed"));
