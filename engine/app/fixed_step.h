#pragma once
// Fixed-step simulation clock, decoupled from rendering. The simulation always advances in whole
// steps of 1/sim_hz seconds (default 60 Hz), so its results depend only on the number of steps and the
// seed, never on how fast frames render.
//   - Headless: frame k ends at exactly k / frame_hz seconds; the number of steps due is computed in
//     integers (floor(k * sim_hz / frame_hz)), so there is no floating-point drift and runs reproduce.
//   - Windowed: real elapsed time accumulates; at most max_steps per frame (a long stall does not
//     spiral), and the remainder carries over.
#include <cstdint>

namespace cumulo::app {

class FixedStepClock {
 public:
  explicit FixedStepClock(uint32_t sim_hz = 60, uint32_t max_steps_per_frame = 8);

  // Headless: steps to run so that the simulation reaches the end of frame `frame_index` (1-based)
  // at frame_hz frames per second. Call once per frame in increasing order.
  uint32_t steps_for_fixed_frame(uint64_t frame_index, uint32_t frame_hz);
  // Windowed: steps to run for `real_seconds` of wall time since the last frame.
  uint32_t steps_for_real_time(double real_seconds);
  // Runs `seconds` of simulation at once (for --start-at): returns the steps (rounded to nearest).
  uint64_t steps_for_fast_forward(double seconds) const;

  void on_steps_run(uint64_t steps) { ticks_ += steps; }
  uint32_t sim_hz() const { return sim_hz_; }
  double step_seconds() const { return 1.0 / sim_hz_; }
  uint64_t ticks() const { return ticks_; }
  double sim_seconds() const { return static_cast<double>(ticks_) / sim_hz_; }
  // Fraction of a step the real time is ahead of the simulation (windowed interpolation), 0..1.
  double alpha() const { return accumulator_ * sim_hz_; }

 private:
  uint32_t sim_hz_, max_steps_;
  uint64_t ticks_ = 0;
  uint64_t fixed_base_ticks_ = 0;  // ticks before the first fixed frame (fast-forward)
  bool fixed_started_ = false;
  double accumulator_ = 0.0;
};

}  // namespace cumulo::app
