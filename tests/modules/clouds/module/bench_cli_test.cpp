// `cumulo bench` through the real executable on a reduced matrix (one view, two ablations, both modes,
// tiny size): it runs clean and writes the JSON the issue names. Its numbers are for people to read,
// never asserted here.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "modules/clouds/bench/bench_runs.h"
#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

TEST(BenchCli, WritesTheTableAndTheJson) {
  fs::path out = cumulo::test::unique_temp_path("cumulo_bench") += ".json";
  const fs::path images = cumulo::test::unique_temp_path("cumulo_bench_images");
  auto r = cumulo::test::run_cumulo("bench --size 64x36 --frames 1 --warmup 1 --rounds 2 --views ground --ablations base,full --out " +
                                    out.string() + " --images " + images.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("| view | ablation | mode |"), std::string::npos) << r.output;
  // A progress line per run and round (the matrix, then full with the light grid updating every frame,
  // run twice in turn).
  // A view's two modes run back to back (the split's saving compares them within a round).
  EXPECT_NE(r.output.find("[3/12] ground full 30 Hz"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[4/12] ground full 60 Hz"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("[12/12] ground full (light grid updating) 60 Hz"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| view | full vs base 30 Hz |"), std::string::npos) << r.output;  // the targets table
  std::ifstream f(out);
  auto j = nlohmann::json::parse(f);
  EXPECT_FALSE(j["device"]["name"].get<std::string>().empty());
  EXPECT_EQ(j["size"][0], 64);
  EXPECT_EQ(j["frames"], 1);
  EXPECT_EQ(j["frames_full_method"], 4);  // a full run as long as a slower one (bench_runs.h)
  EXPECT_EQ(j["rounds"], 2);
  // The converged images the split's PSNR compares, one per run of the matrix.
  for (const char* name : {"ground_base_30hz.png", "ground_base_60hz.png", "ground_full_30hz.png", "ground_full_60hz.png"})
    EXPECT_GT(fs::exists(images / name) ? fs::file_size(images / name) : 0u, 0u) << name;
  fs::remove_all(images);
  EXPECT_GT(j["memory"]["cloudscape_compressed"].get<uint64_t>(), 0u);
  EXPECT_LE(j["memory"]["cloudscape_compressed"].get<uint64_t>(), 25200000u);  // the talk's budget per cloudscape
  ASSERT_EQ(j["runs"].size(), 4u);
  for (auto& run : j["runs"]) {
    for (const char* key : {"view", "ablation", "mode", "cloud_ms", "geometry_ms", "sky_layer_and_shafts_ms", "steps_per_pixel",
                            "passes"})
      EXPECT_TRUE(run.contains(key)) << key;
    EXPECT_GT(run["cloud_ms"].get<double>(), 0.0);
    // The headless loop's wall clock holds the CPU part and the wait for the GPU.
    EXPECT_GT(run["cpu_ms"].get<double>(), 0.0) << run.dump();
    EXPECT_GT(run["wall_ms"].get<double>(), run["cpu_ms"].get<double>()) << run.dump();
    // Every round's figures, not only the pooled median.
    ASSERT_EQ(run["rounds"].size(), 2u) << run.dump();
    for (auto& round : run["rounds"]) {
      EXPECT_GT(round["cloud_ms"].get<double>(), 0.0) << run.dump();
      EXPECT_GE(round["wall_ms"].get<double>(), round["cpu_ms"].get<double>()) << run.dump();
    }
    // The sample level's 2.5D sky (it has a WeatherScheduler), timed as its own pass, outside cloud_ms.
    EXPECT_TRUE(run["passes"].contains("clouds.sky_layer")) << run.dump();
    EXPECT_GT(run["sky_layer_and_shafts_ms"].get<double>(), 0.0);
    // Apart as well: the sky layer's passes and the shafts' (the ground camera looks toward no sun: shafts may be 0).
    EXPECT_GT(run["sky_layer_ms"].get<double>(), 0.0);
    EXPECT_GE(run["light_shafts_ms"].get<double>(), 0.0);
    EXPECT_NEAR(run["sky_layer_ms"].get<double>() + run["light_shafts_ms"].get<double>(),
                run["sky_layer_and_shafts_ms"].get<double>(), 0.5 * run["sky_layer_and_shafts_ms"].get<double>() + 1.0);
    EXPECT_TRUE(run["passes"].contains(run["mode"] == 30 ? "clouds.march" : "clouds.march_far")) << run.dump();
    // 60 Hz runs carry the PSNR of their final image against the 30 Hz run's: close, not identical.
    if (run["mode"] == 60) {
      EXPECT_GT(run["psnr_vs_30hz_db"].get<double>(), 20.0) << run.dump();
      EXPECT_LT(run["psnr_vs_30hz_db"].get<double>(), 99.0) << run.dump();
    }
  }
  // The simulation's CPU time per 60 Hz frame, timed apart from the still matrix.
  EXPECT_GT(j["cpu"]["simulation_ms_per_frame_60hz"].get<double>(), 0.0);
  EXPECT_NE(r.output.find("CPU per frame: the simulation"), std::string::npos) << r.output;
  ASSERT_EQ(j["summary"].size(), 1u);
  const auto& sum = j["summary"][0];
  EXPECT_EQ(sum["view"], "ground");
  EXPECT_GT(sum["full_vs_base_30"].get<double>(), 0.0);
  EXPECT_GE(sum["light_grid_share_60"].get<double>(), 0.0);  // 0 once the grid rests (a still sun)
  EXPECT_GT(sum["light_grid_share_updating_60"].get<double>(), 0.0);
  EXPECT_LT(sum["light_grid_share_updating_60"].get<double>(), 1.0);
  EXPECT_EQ(sum["split_psnr_db"], j["runs"][3]["psnr_vs_30hz_db"]);
  ASSERT_EQ(sum["full_vs_base_30_rounds"].size(), 2u);
  ASSERT_EQ(sum["split_saving_rounds"].size(), 2u);
  for (auto& ratio : sum["full_vs_base_30_rounds"]) EXPECT_GT(ratio.get<double>(), 0.0);
  EXPECT_GT(sum["fps_wall_60"].get<double>(), 0.0);
  EXPECT_LE(sum["fps_wall_60"].get<double>(), sum["fps_60"].get<double>() * 1.001);  // the wall holds the GPU's time
  // The full method takes fewer steps than the uniform base march (the SDF skips empty space).
  ASSERT_EQ(j["runs"][2]["ablation"], "full");
  EXPECT_LT(j["runs"][2]["steps_per_pixel"].get<double>(), j["runs"][0]["steps_per_pixel"].get<double>());
  fs::remove(out);
}

// A run's measured frames split into the chunks its modes take turns in: every frame measured once.
TEST(BenchCli, ARunsFramesSplitIntoTheChunksItsModesTakeTurnsIn) {
  using namespace cumulo::clouds::bench;
  for (uint32_t frames : {1u, 3u, 8u, 32u, 33u}) {
    uint32_t sum = 0;
    for (uint32_t c = 0; c < kModeChunks; ++c) {
      sum += chunk_frames(frames, c);
      EXPECT_LE(chunk_frames(frames, c), frames / kModeChunks + 1);
    }
    EXPECT_EQ(sum, frames);
  }
}

TEST(BenchCli, BadMatrixIsRefused) {
  auto r = cumulo::test::run_cumulo("bench --ablations fastest");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--ablations"), std::string::npos) << r.output;
  r = cumulo::test::run_cumulo("bench --views nowhere --frames 1 --warmup 0 --size 32x18");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("nowhere"), std::string::npos) << r.output;
}
