#pragma once
// The CloudsRun fixture: `cumulo run` with the clouds module in this process, headless on lavapipe with
// validation, on tests/modules/clouds/module/data/level.json (one small baked cloud) edited per test.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/app/application.h"
#include "engine/core/file_io.h"
#include "modules/clouds/clouds_module.h"
#include "tests/support/png_read.h"
#include "tests/support/temp_dir.h"

namespace cumulo::test {

namespace fs = std::filesystem;

// Rec. 709 luminance of an 8-bit pixel.
inline double luminance(const Png& p, int x, int y) {
  return 0.2126 * p.at(x, y, 0) + 0.7152 * p.at(x, y, 1) + 0.0722 * p.at(x, y, 2);
}

class CloudsRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::unique_temp_path("cumulo_clouds_run");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file("tests/modules/clouds/module/data/small_cloud.json", dir_ / "small_cloud.json");
    level_text_ = read_file_text("tests/modules/clouds/module/data/level.json");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes the level with `from` replaced by `to` and returns its path.
  fs::path level(const std::string& name, const std::string& from = "", const std::string& to = "") {
    std::string text = level_text_;
    if (!from.empty()) {
      size_t p = text.find(from);
      EXPECT_NE(p, std::string::npos) << from;
      if (p != std::string::npos) text.replace(p, from.size(), to);
    }
    fs::path file = dir_ / (name + ".json");
    write_file_atomic(file, text);
    return file;
  }

  // Runs `cumulo run LEVEL --headless` in this process with a fresh clouds module; returns the exit code.
  int run(const fs::path& level_file, const std::string& shot, std::vector<std::string> extra = {}, int frames = 3) {
    // frames < 0: no --frames flag.
    std::vector<std::string> args{"run", level_file.string(), "--headless", "--size", "160x90",
                                  "--screenshot", (dir_ / shot).string(), "--dump-graph", (dir_ / (shot + ".txt")).string()};
    if (frames >= 0) args.insert(args.begin() + 3, {"--frames", std::to_string(frames)});
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    app::Modules modules{clouds::make_clouds_module()};
    auto o = app::parse_run_options(int(argv.size()), argv.data(), modules);
    return o ? app::run_level(*o, modules) : -1;
  }

  // Mean absolute difference per pixel column band and its centroid (x) where the images differ.
  static double mean_diff(const Png& a, const Png& b) {
    double d = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) d += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
    return d / double(a.rgba.size());
  }
  static double diff_centroid_x(const Png& a, const Png& b) {
    double sum = 0, wsum = 0;
    for (int y = 0; y < a.h; ++y)
      for (int x = 0; x < a.w; ++x) {
        double d = 0;
        for (int c = 0; c < 3; ++c) d += std::abs(a.at(x, y, c) - b.at(x, y, c));
        sum += d * x;
        wsum += d;
      }
    return wsum > 0 ? sum / wsum : -1.0;
  }

  fs::path dir_;
  std::string level_text_;
};

}  // namespace cumulo::test
