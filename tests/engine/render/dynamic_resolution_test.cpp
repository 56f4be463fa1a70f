#include "engine/render/dynamic_resolution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/core/error.h"

using namespace cumulo;
using namespace cumulo::render;

namespace {

// A device whose frame is `fixed` ms that do not scale plus `scaled` ms at scale 1 that go with the pixels.
struct ModelDevice {
  double fixed, scaled;
  double frame_ms(float s) const { return fixed + scaled * double(s) * double(s); }
};

// Runs `frames` frames through the controller; returns the scale it ends at.
float run(DynamicResolution& d, const ModelDevice& dev, int frames, BudgetMode mode = BudgetMode::Hz60) {
  float s = d.scale();
  for (int i = 0; i < frames; ++i) s = d.update(dev.frame_ms(s), mode);
  return s;
}

}  // namespace

TEST(FrameBudget, EachModeTimesTheDeviceFactor) {
  EXPECT_DOUBLE_EQ(default_budget_scale(false), 1.0);
  EXPECT_DOUBLE_EQ(default_budget_scale(true), 3.0);
  EXPECT_NEAR(frame_budget_ms(BudgetMode::Hz60, 1.0), 16.667, 1e-3);
  EXPECT_NEAR(frame_budget_ms(BudgetMode::Hz60, 3.0), 50.0, 1e-9);  // lavapipe's 20 fps
  EXPECT_NEAR(frame_budget_ms(BudgetMode::Hz40, 3.0), 75.0, 1e-9);
  EXPECT_NEAR(frame_budget_ms(BudgetMode::Hz30, 3.0), 100.0, 1e-9);
}

TEST(DynamicResolution, ABudgetTooSmallForTheDeviceLowersTheScaleToItsFloor) {
  DynamicResolution d;
  d.set_enabled(true);
  d.set_budget_scale(1.0);  // 16.7 ms at 60 Hz
  const ModelDevice dev{10.0, 90.0};  // 100 ms at full scale, 32.5 ms at 0.5: never fits
  EXPECT_FLOAT_EQ(run(d, dev, 200), DynamicResolution::kMinScale);
  EXPECT_GE(d.changes(), 1u);
}

TEST(DynamicResolution, ALargeBudgetRaisesTheScaleBackToOne) {
  DynamicResolution d;
  d.set_enabled(true);
  d.set_budget_scale(0.1);
  const ModelDevice dev{2.0, 30.0};
  ASSERT_FLOAT_EQ(run(d, dev, 200), DynamicResolution::kMinScale);
  d.set_budget_scale(10.0);  // 167 ms
  float s = DynamicResolution::kMinScale, last = s;
  for (int i = 0; i < 300; ++i) {
    s = d.update(dev.frame_ms(s), BudgetMode::Hz60);
    EXPECT_GE(s, last) << "a large budget never lowers the scale (frame " << i << ")";
    last = s;
  }
  EXPECT_FLOAT_EQ(s, 1.0f);
}

TEST(DynamicResolution, SettlesOnTheLargestLevelThatFitsAndStaysThere) {
  DynamicResolution d;
  d.set_enabled(true);
  d.set_budget_scale(3.0);  // 50 ms
  // 20 ms fixed + 60 ms x s^2: 0.625 gives 43.4 ms, 0.75 gives 53.75 ms (over).
  const ModelDevice dev{20.0, 60.0};
  EXPECT_FLOAT_EQ(run(d, dev, 120), 0.625f);
  const uint32_t changes = d.changes();
  EXPECT_FLOAT_EQ(run(d, dev, 400), 0.625f);
  EXPECT_EQ(d.changes(), changes) << "the scale oscillates";
  EXPECT_LE(dev.frame_ms(d.scale()), d.budget_ms(BudgetMode::Hz60));
}

TEST(DynamicResolution, OneSlowFrameDoesNotMoveTheScale) {
  DynamicResolution d;
  d.set_enabled(true);
  d.set_budget_scale(3.0);
  float s = 1.0f;
  for (int i = 0; i < 100; ++i) s = d.update(i % 10 == 5 ? 400.0 : 30.0, BudgetMode::Hz60);  // a hitch each 10 frames
  EXPECT_FLOAT_EQ(s, 1.0f);
  EXPECT_EQ(d.changes(), 0u);
}

TEST(DynamicResolution, DisabledKeepsFullResolution) {
  DynamicResolution d;
  d.set_budget_scale(0.01);
  for (int i = 0; i < 50; ++i) EXPECT_FLOAT_EQ(d.update(500.0, BudgetMode::Hz60), 1.0f);
  d.set_enabled(true);
  EXPECT_LT(run(d, {10.0, 90.0}, 100), 1.0f);
  d.set_enabled(false);
  EXPECT_FLOAT_EQ(d.scale(), 1.0f);
}

TEST(DynamicResolution, TheBudgetFollowsTheMode) {
  DynamicResolution d;
  d.set_enabled(true);
  d.set_budget_scale(1.0);
  const ModelDevice dev{5.0, 20.0};  // 25 ms: inside 30 Hz's 33.3 ms, over 60 Hz's 16.7 ms
  EXPECT_FLOAT_EQ(run(d, dev, 100, BudgetMode::Hz30), 1.0f);
  EXPECT_LT(run(d, dev, 100, BudgetMode::Hz60), 1.0f);
  EXPECT_FLOAT_EQ(run(d, dev, 200, BudgetMode::Hz30), 1.0f);
}

TEST(DynamicResolution, RejectsABadBudgetScaleAndIgnoresBadTimes) {
  DynamicResolution d;
  EXPECT_THROW(d.set_budget_scale(0.0), Error);
  EXPECT_THROW(d.set_budget_scale(-1.0), Error);
  EXPECT_THROW(d.set_budget_scale(std::numeric_limits<double>::quiet_NaN()), Error);
  d.set_enabled(true);
  for (int i = 0; i < 50; ++i) {
    EXPECT_FLOAT_EQ(d.update(std::numeric_limits<double>::quiet_NaN(), BudgetMode::Hz30), 1.0f);
    EXPECT_FLOAT_EQ(d.update(-5.0, BudgetMode::Hz30), 1.0f);
    EXPECT_FLOAT_EQ(d.update(std::numeric_limits<double>::infinity(), BudgetMode::Hz30), 1.0f);
  }
}

TEST(DynamicResolution, LevelsAreEighthsFromOneHalf) {
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(0.2f), 0.5f);
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(0.74f), 0.625f);
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(0.75f), 0.75f);
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(0.9f), 0.875f);
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(3.0f), 1.0f);
  EXPECT_FLOAT_EQ(DynamicResolution::level_at_or_below(std::nanf("")), 0.5f);
}
