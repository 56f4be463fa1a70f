#include "engine/app/fixed_step.h"

#include <gtest/gtest.h>

using namespace cumulo::app;

TEST(FixedStep, HeadlessFramesAdvanceExactlyOneOverModeSeconds) {
  // 40 Hz frames over a 60 Hz simulation: 1.5 steps per frame on average, never drifting.
  FixedStepClock clock(60);
  uint64_t total = 0;
  for (uint64_t f = 1; f <= 400; ++f) {
    uint32_t s = clock.steps_for_fixed_frame(f, 40);
    EXPECT_TRUE(s == 1 || s == 2) << f;
    clock.on_steps_run(s);
    total += s;
  }
  EXPECT_EQ(total, 600u);  // 400 frames / 40 Hz = 10 s = 600 steps exactly
  EXPECT_DOUBLE_EQ(clock.sim_seconds(), 10.0);
}

TEST(FixedStep, ThirtyHzIsTwoStepsPerFrame) {
  FixedStepClock clock(60);
  for (uint64_t f = 1; f <= 10; ++f) {
    uint32_t s = clock.steps_for_fixed_frame(f, 30);
    EXPECT_EQ(s, 2u);
    clock.on_steps_run(s);
  }
}

TEST(FixedStep, FastForwardThenFramesContinueFromThere) {
  FixedStepClock clock(60);
  uint64_t ff = clock.steps_for_fast_forward(2.5);
  EXPECT_EQ(ff, 150u);
  clock.on_steps_run(ff);
  uint32_t s = clock.steps_for_fixed_frame(1, 60);
  EXPECT_EQ(s, 1u);
  clock.on_steps_run(s);
  EXPECT_EQ(clock.ticks(), 151u);
}

TEST(FixedStep, RealTimeAccumulatesAndCapsAStall) {
  FixedStepClock clock(60, 4);
  EXPECT_EQ(clock.steps_for_real_time(0.010), 0u);  // less than a step
  EXPECT_EQ(clock.steps_for_real_time(0.010), 1u);  // 20 ms -> one step, 3.3 ms left
  EXPECT_NEAR(clock.alpha(), (0.020 - 1.0 / 60.0) * 60.0, 1e-9);
  EXPECT_EQ(clock.steps_for_real_time(5.0), 4u);    // a 5 s stall runs at most 4 steps
  EXPECT_LE(clock.alpha(), 1.0 + 1e-9);
  EXPECT_EQ(clock.steps_for_real_time(-1.0), 0u);   // clocks never go backward
}
