// On Mesa's CPU driver nothing is compiled again once a view is running: lavapipe (Mesa 22.3) compiles a
// compute shader again at every bind when a loop bound or a much-used variable comes from the parameter
// blocks alone (shaders/engine/runtime_uniform.glsl), which cost the 2.5D sky, the light shafts and the
// aerial perspective 1.5-7 ms a frame each. `cumulo run` is run with a preloaded counter of the driver's JIT
// compiles (jit_count_preload.cpp) for 4 and for 10 frames: the six more frames must compile nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/engine/app/cli_test_util.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;

namespace {

// JIT compiles of one headless run; -1 when the run failed.
long jit_compiles(const std::string& camera, int mode, int frames, const fs::path& dir, std::string& output) {
  const fs::path count = dir / (camera + std::to_string(mode) + "_" + std::to_string(frames));
  const std::string level = std::string(CUMULO_SOURCE_DIR) + "/content/levels/sample/level.json";
  auto r = cumulo::test::run_cumulo("run " + level + " --headless --size 64x36 --frames " + std::to_string(frames) +
                                        " --camera " + camera + " --mode " + std::to_string(mode),
                                    "LD_PRELOAD=" + std::string(CUMULO_JIT_COUNT_LIB) + " JIT_COUNT_FILE=" + count.string());
  output = r.output;
  if (r.exit_code != 0) return -1;
  std::ifstream f(count);
  long n = -1;
  f >> n;
  return n;
}

}  // namespace

TEST(SteadyStateJit, NoShaderIsCompiledAgainOnceAViewRuns) {
  cumulo::test::TempDir tmp("cumulo_steady_jit");
  for (const auto& [camera, mode] : {std::pair<std::string, int>{"ground", 60}, {"mixed", 30}, {"immersed", 60}}) {
    std::string out;
    const long few = jit_compiles(camera, mode, 4, tmp.path, out);
    ASSERT_GE(few, 0) << out;
    if (few == 0) GTEST_SKIP() << "the Vulkan driver compiles through no LLVM JIT (not Mesa's CPU driver)";
    const long more = jit_compiles(camera, mode, 10, tmp.path, out);
    ASSERT_GE(more, 0) << out;
    EXPECT_EQ(more, few) << camera << " at " << mode << " Hz: " << (more - few) << " JIT compiles in 6 more frames";
  }
}
