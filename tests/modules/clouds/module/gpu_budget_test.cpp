// Issue 25: a GPU memory budget that makes the device look small (CUMULO_GPU_MEMORY_BUDGET_MB). The sample level
// through the real executable with the validation layers on: what does not fit is left out with a message (a
// cloudscape asset), or refused with one naming the resource, the need and the budget (the engine's own resources,
// a window too large); never a crash, a device loss or a validation error (which exits 3).
#include <gtest/gtest.h>

#include <string>

#include "tests/engine/app/cli_test_util.h"

namespace {

const std::string kRun = "run content/levels/sample/level.json --headless --frames 3 --camera stormbird --size ";

cumulo::test::CliResult run_with_budget(int mb, const std::string& size) {
  return cumulo::test::run_cumulo(kRun + size, "CUMULO_VALIDATION=1 CUMULO_GPU_MEMORY_BUDGET_MB=" + std::to_string(mb));
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
size_t count(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(GpuBudget, AnAssetThatDoesNotFitIsLeftOutAndTheLevelRuns) {
  // The sample's two cloudscape assets take about 105 and 28 MB; at 150 MB the first that does not fit is left out.
  const auto r = run_with_budget(150, "160x90");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "not drawn:")) << r.output;
  EXPECT_TRUE(has(r.output, "CUMULO_GPU_MEMORY_BUDGET_MB")) << r.output;
  // Said once (one asset), not every frame.
  EXPECT_EQ(count(r.output, "not drawn:"), 1u) << r.output;
}

TEST(GpuBudget, BothAssetsLeftOutAtASmallerBudget) {
  const auto r = run_with_budget(60, "160x90");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "cloudscape-")) << r.output;
  EXPECT_TRUE(has(r.output, "storm_cloud-")) << r.output;
  EXPECT_EQ(count(r.output, "not drawn:"), 2u) << r.output;
}

TEST(GpuBudget, WhatTheEngineCannotDoWithoutIsRefusedWithAMessage) {
  const auto r = run_with_budget(20, "160x90");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "error: ")) << r.output;
  EXPECT_TRUE(has(r.output, "of the 20.0 MiB budget are in use (CUMULO_GPU_MEMORY_BUDGET_MB)")) << r.output;
}

TEST(GpuBudget, AWindowTooLargeForTheBudgetIsRefusedNamingTheResource) {
  const auto r = run_with_budget(250, "3840x2160");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "MiB of GPU memory, but")) << r.output;
}

TEST(GpuBudget, AMalformedBudgetIsNamed) {
  const auto r = cumulo::test::run_cumulo(kRun + "64x36", "CUMULO_GPU_MEMORY_BUDGET_MB=lots");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "CUMULO_GPU_MEMORY_BUDGET_MB: expected a positive number of MiB, got \"lots\"")) << r.output;
}
