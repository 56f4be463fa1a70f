// Issue 25: `cumulo bake` killed (SIGKILL) at every step of writing its outputs over an earlier bake (each file to a
// temporary, the journal, the renames, the journal removed). The next reader of the folder (a level naming it: the
// same call `cumulo run` makes) gets the whole earlier bake or the whole new one, never files of both.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "engine/core/file_io.h"
#include "modules/clouds/scene/cloudscape_assets.h"
#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

namespace {

// Every file's bytes; the report without its timings (they differ from one run of the same bake to the next).
std::map<std::string, std::vector<uint8_t>> folder_files(const fs::path& dir) {
  std::map<std::string, std::vector<uint8_t>> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    std::vector<uint8_t> bytes = cumulo::read_file_bytes(e.path());
    if (e.path().filename() == "bake_report.json") {
      nlohmann::json j = nlohmann::json::parse(bytes.begin(), bytes.end());
      j.erase("timings_s");
      const std::string text = j.dump();
      bytes.assign(text.begin(), text.end());
    }
    files[e.path().filename().string()] = std::move(bytes);
  }
  return files;
}

}  // namespace

TEST(BakeKill, ABakeKilledAtAnyStepLeavesTheEarlierBakeOrTheNewOne) {
  const fs::path root = cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_bake_kill"));
  const std::string recipe = "tests/modules/clouds/module/data/small_cloud.json";
  auto bake = [&](const fs::path& out, int seed, const std::string& env) {
    return cumulo::test::run_cumulo("bake " + recipe + " -o " + out.string() + " --seed " + std::to_string(seed), env);
  };
  // Both bakes made in `out` itself (the report names its folder), kept aside.
  const fs::path out = root / "out";
  ASSERT_EQ(bake(out, 2, "").exit_code, 0);
  fs::rename(out, root / "new");
  ASSERT_EQ(bake(out, 1, "").exit_code, 0);
  fs::rename(out, root / "old");
  const auto old_set = folder_files(root / "old"), new_set = folder_files(root / "new");
  ASSERT_NE(old_set.at("modeling.nvdf"), new_set.at("modeling.nvdf"));
  int killed = 0, mixed_on_disk = 0;
  for (int step = 1; step <= 20; ++step) {
    fs::remove_all(out);
    fs::copy(root / "old", out);
    const auto r = bake(out, 2, "CUMULO_KILL_AT_SAVE_STEP=" + std::to_string(step));
    const bool completed = r.exit_code == 0;
    killed += completed ? 0 : 1;
    {
      auto now = folder_files(out);
      bool has_old = false, has_new = false;
      for (const auto& [name, bytes] : old_set)
        if (now.count(name) && bytes != new_set.at(name)) {
          has_old = has_old || now[name] == bytes;
          has_new = has_new || now[name] == new_set.at(name);
        }
      mixed_on_disk += has_old && has_new ? 1 : 0;
    }
    // What a level naming the folder reads.
    EXPECT_EQ(cumulo::clouds::prepare_cloudscape_asset(out, "test level"), out);
    const auto after = folder_files(out);
    EXPECT_TRUE(after == old_set || after == new_set) << "step " << step << ": a mix of two bakes\n" << r.output;
    if (completed) {
      EXPECT_EQ(after, new_set);
      break;
    }
  }
  EXPECT_GE(killed, 8) << "six files, a journal and their renames";
  EXPECT_GT(mixed_on_disk, 0) << "no kill fell between two renames";
  fs::remove_all(root);
}
