#pragma once
// Budget modes that hold a budget: each mode's frame time (33.3 / 25 / 16.7 ms) times a device factor is
// the frame's budget, and a dynamic resolution scale for the passes that can scale (the cloud march and
// its reconstruction, the 2.5D sky) keeps the frame's GPU time inside it.
//
// The device factor: 1 on a GPU. A CPU device (lavapipe) cannot reach 16.7 ms at any useful size, so its
// default is 3: 60 Hz plans for 50 ms (20 fps, flyable), 40 Hz for 75 ms, 30 Hz for 100 ms.
// `--budget-scale X` overrides it.
//
// The controller (update() once per completed frame, with that frame's GPU ms):
// - the scale is one of the levels 0.5, 0.625, .. 1 (few render-graph shapes: each new one is compiled
//   and allocated once, and a history resized once);
// - after a change it ignores kSettleFrames frames (timings arrive a frame or two late, and frames at the
//   old scale are no evidence about the new one), then judges the median of kWindowFrames frames;
// - over the budget: down to the level that would fit were the whole frame to scale with its pixels
//   (s' = s sqrt(budget / ms)), at least one level. Part of a frame does not scale (geometry, the light
//   grid), so the frame may still be over: the next window steps again;
// - under the budget by enough that the next level up would still fit were the whole frame to scale
//   with it (ms (s'/s)^2 <= kRaiseHeadroom budget): up one level. Since only part scales, the frame lands
//   lower than that: a raise never overshoots into a drop (no oscillation).
// Off (the scale stays 1) for headless runs unless asked, for the bench's fixed runs and for soaks: their
// pictures and timings must not depend on the machine's speed.
#include <cstdint>
#include <vector>

#include "engine/render/budget_mode.h"

namespace cumulo::render {

// The default device factor: 3 on a CPU device, else 1.
double default_budget_scale(bool cpu_device);
// The mode's frame time times the device factor.
double frame_budget_ms(BudgetMode mode, double budget_scale);

class DynamicResolution {
 public:
  static constexpr float kMinScale = 0.5f;
  static constexpr float kStep = 0.125f;
  static constexpr uint32_t kSettleFrames = 3;
  static constexpr uint32_t kWindowFrames = 8;
  static constexpr double kRaiseHeadroom = 0.85;

  void set_enabled(bool on);
  bool enabled() const { return enabled_; }
  // Throws cumulo::Error unless finite and > 0.
  void set_budget_scale(double s);
  double budget_scale() const { return budget_scale_; }
  double budget_ms(BudgetMode mode) const { return frame_budget_ms(mode, budget_scale_); }

  // One completed frame's GPU milliseconds (the sum of its passes; the wall clock where the device has no
  // timestamps) in `mode`; returns the scale for the next frame (1 while disabled). A change of mode
  // starts a new window. Non-finite or negative times are ignored.
  float update(double frame_ms, BudgetMode mode);
  float scale() const { return enabled_ ? scale_ : 1.0f; }
  uint32_t changes() const { return changes_; }  // scale changes since construction

  // The level at or below `s` (clamped to [kMinScale, 1]).
  static float level_at_or_below(float s);

 private:
  void restart_window();
  bool enabled_ = false;
  double budget_scale_ = 1.0;
  float scale_ = 1.0f;
  BudgetMode mode_ = BudgetMode::Hz30;
  uint32_t settle_ = 0;
  uint32_t changes_ = 0;
  std::vector<double> window_;
};

}  // namespace cumulo::render
