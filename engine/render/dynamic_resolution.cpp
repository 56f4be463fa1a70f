#include "engine/render/dynamic_resolution.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"

namespace cumulo::render {

double default_budget_scale(bool cpu_device) { return cpu_device ? 3.0 : 1.0; }

double frame_budget_ms(BudgetMode mode, double budget_scale) { return budget_frame_ms(mode) * budget_scale; }

void DynamicResolution::set_enabled(bool on) {
  if (on == enabled_) return;
  enabled_ = on;
  scale_ = 1.0f;
  restart_window();
}

void DynamicResolution::set_budget_scale(double s) {
  if (!std::isfinite(s) || !(s > 0.0)) fail("budget scale %g: expected a number > 0", s);
  budget_scale_ = s;
  restart_window();
}

float DynamicResolution::level_at_or_below(float s) {
  if (!(s >= kMinScale)) return kMinScale;
  if (s >= 1.0f) return 1.0f;
  // A hair of tolerance so that an exact level (0.75 from 0.75000006) stays itself.
  return std::max(kMinScale, std::floor(s / kStep + 1e-4f) * kStep);
}

void DynamicResolution::restart_window() {
  window_.clear();
  settle_ = kSettleFrames;
}

float DynamicResolution::update(double frame_ms, BudgetMode mode) {
  if (!enabled_) return 1.0f;
  if (mode != mode_) {
    mode_ = mode;
    restart_window();
  }
  if (!std::isfinite(frame_ms) || frame_ms < 0.0) return scale_;
  if (settle_ > 0) {
    --settle_;
    return scale_;
  }
  window_.push_back(frame_ms);
  if (window_.size() < kWindowFrames) return scale_;
  std::vector<double> sorted = window_;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double ms = sorted[sorted.size() / 2];
  window_.clear();
  const double budget = budget_ms(mode);
  float next = scale_;
  if (ms > budget && scale_ > kMinScale) {
    const float fit = level_at_or_below(scale_ * float(std::sqrt(budget / ms)));
    next = std::min(fit, scale_ - kStep);
  } else if (scale_ < 1.0f) {
    const float up = std::min(1.0f, scale_ + kStep);
    const double predicted = ms * double(up / scale_) * double(up / scale_);
    if (predicted <= kRaiseHeadroom * budget) next = up;
  }
  next = std::clamp(next, kMinScale, 1.0f);
  if (next != scale_) {
    scale_ = next;
    ++changes_;
    settle_ = kSettleFrames;
  }
  return scale_;
}

}  // namespace cumulo::render
