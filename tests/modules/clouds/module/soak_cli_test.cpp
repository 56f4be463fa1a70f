// `cumulo soak`, the shorter form (issue 25): 1,000 frames of the sample level in four laps at a tiny size, with the
// validation layers on (the suite's CUMULO_VALIDATION=1). Whatever the soak counts must stay flat from lap to lap,
// no frame may hold a NaN or an infinity and no validation message may appear; resident memory is measured in the
// long run without the layers (scripts/soak.sh), so here it is only recorded.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

TEST(SoakCli, AThousandFramesInFourLapsLeaveNothingGrowing) {
  const fs::path out = cumulo::test::unique_temp_path("cumulo_soak") += ".json";
  auto r = cumulo::test::run_cumulo("soak --frames 1000 --lap 250 --size 64x36 --weather-cycle off --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream f(out);
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["windows"].size(), 4u);
  for (const auto& w : j["windows"]) {
    EXPECT_EQ(w["frames"], 250);
    EXPECT_EQ(w["probed_frames"], 250) << w.dump();  // every frame went through the GPU's check
    EXPECT_EQ(w["nonfinite_frames"], 0);
    EXPECT_EQ(w["validation_errors"], 0);
    EXPECT_GT(w["events_fired"].get<int>(), 0);  // lightning, the Stormbird
    EXPECT_GT(w["resident_bytes"].get<uint64_t>(), 0u);
  }
  for (const auto& c : j["checks"])
    if (c["counted"].get<bool>()) EXPECT_TRUE(c["pass"].get<bool>()) << c.dump();
  // The loop went through the level's cameras and its weather zone.
  EXPECT_GT(j["path_m"].get<double>(), 1000.0);
  fs::remove(out);
}
