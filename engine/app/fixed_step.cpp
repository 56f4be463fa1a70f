#include "engine/app/fixed_step.h"

#include <algorithm>
#include <cmath>

namespace cumulo::app {

FixedStepClock::FixedStepClock(uint32_t sim_hz, uint32_t max_steps) : sim_hz_(std::max(1u, sim_hz)), max_steps_(std::max(1u, max_steps)) {}

uint32_t FixedStepClock::steps_for_fixed_frame(uint64_t frame_index, uint32_t frame_hz) {
  if (!fixed_started_) {
    fixed_base_ticks_ = ticks_;
    fixed_started_ = true;
  }
  uint64_t target = fixed_base_ticks_ + frame_index * sim_hz_ / std::max(1u, frame_hz);
  return target > ticks_ ? static_cast<uint32_t>(target - ticks_) : 0u;
}

uint32_t FixedStepClock::steps_for_real_time(double real_seconds) {
  accumulator_ += std::max(0.0, real_seconds);
  double step = step_seconds();
  uint32_t steps = 0;
  while (accumulator_ >= step && steps < max_steps_) {
    accumulator_ -= step;
    ++steps;
  }
  if (steps == max_steps_ && accumulator_ >= step) accumulator_ = 0.0;  // drop the backlog after a stall
  return steps;
}

uint64_t FixedStepClock::steps_for_fast_forward(double seconds) const {
  return seconds <= 0.0 ? 0 : static_cast<uint64_t>(std::llround(seconds * sim_hz_));
}

}  // namespace cumulo::app
