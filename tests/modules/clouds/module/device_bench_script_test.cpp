// scripts/device-bench.sh, the one-command GPU bench, run here on lavapipe from a bundle-shaped folder
// (the launcher and bin/cumulo of scripts/bundle.sh, pointing at this build) at two tiny sizes: it runs
// the bench at each size and joins them into one JSON named after the device, as it does on a GPU machine.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(DeviceBenchScript, BenchesEverySizeFromABundleIntoOneJson) {
  cumulo::test::TempDir tmp("cumulo_device_bench");
  const fs::path bundle = tmp.path / "bundle";
  fs::create_directories(bundle / "bin");
  fs::create_symlink(CUMULO_EXE, bundle / "bin" / "cumulo");
  {
    std::ofstream launcher(bundle / "cumulo");
    launcher << "#!/bin/sh\nexport CUMULO_ROOT='" << CUMULO_SOURCE_DIR << "'\nexec \"$(dirname \"$0\")/bin/cumulo\" \"$@\"\n";
  }
  fs::permissions(bundle / "cumulo", fs::perms::owner_all, fs::perm_options::add);
  fs::copy_file(fs::path(CUMULO_SOURCE_DIR) / "scripts" / "device-bench.sh", bundle / "device-bench.sh");
  const fs::path out = tmp.path / "out";
  const auto r = cumulo::test::run_command(
      "env CUMULO_DEVICE_BENCH_SIZES='64x36 96x54' CUMULO_DEVICE_BENCH_VIEWS=ground CUMULO_DEVICE_BENCH_FRAMES=1 "
      "CUMULO_DEVICE_BENCH_WARMUP=1 CUMULO_DEVICE_BENCH_ROUNDS=1 '" + (bundle / "device-bench.sh").string() + "' '" +
      out.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("device-bench: 96x54 done"), std::string::npos) << r.output;
  fs::path json, md;
  for (const auto& e : fs::directory_iterator(out)) {
    if (e.path().extension() == ".json") json = e.path();
    if (e.path().extension() == ".md") md = e.path();
  }
  ASSERT_FALSE(json.empty()) << r.output;
  const nlohmann::json j = nlohmann::json::parse(read_text(json));  // throws (fails) on a malformed join
  ASSERT_EQ(j["sizes"].size(), 2u);
  EXPECT_EQ(j["sizes"]["64x36"]["size"][0], 64);
  EXPECT_EQ(j["sizes"]["96x54"]["size"][0], 96);
  for (const auto& [size, bench] : j["sizes"].items()) {
    EXPECT_FALSE(bench["runs"].empty()) << size;
    EXPECT_EQ(bench["runs"][0]["rounds"].size(), 1u) << size;
  }
  // The file is named after the device the bench ran on.
  const std::string device = j["sizes"]["64x36"]["device"]["name"];
  EXPECT_NE(device.find("llvmpipe"), std::string::npos) << device;
  EXPECT_EQ(json.stem().string().rfind("llvmpipe", 0), 0u) << json;
  const std::string tables = read_text(md);
  EXPECT_NE(tables.find("## 64x36"), std::string::npos);
  EXPECT_NE(tables.find("## 96x54"), std::string::npos);
  EXPECT_NE(tables.find("| view | full vs base 30 Hz |"), std::string::npos);
}

TEST(DeviceBenchScript, NamesAMissingBundle) {
  const auto r = cumulo::test::run_command("env CUMULO_BUNDLE=/nonexistent/bundle '" + std::string(CUMULO_SOURCE_DIR) +
                                  "/scripts/device-bench.sh' /tmp/unused");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/bundle"), std::string::npos) << r.output;
}
