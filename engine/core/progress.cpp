#include "engine/core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace cumulo {

bool Progress::terminal() {
  const char* env = std::getenv("CUMULO_PROGRESS");
  if (env && env[0] == '0') return false;
  return isatty(STDERR_FILENO);
}

Progress::Progress(std::string label, double total) : label_(std::move(label)), total_(std::max(total, 1e-9)) {}

Progress::~Progress() {
  if (!finished_) finish();
}

void Progress::add(double amount) {
  double cur = done_.load();
  while (!done_.compare_exchange_weak(cur, cur + amount)) {
  }
  draw(false);
}

void Progress::set(double done) {
  done_ = done;
  draw(false);
}

void Progress::draw(bool force) {
  if (!terminal()) return;
  std::lock_guard lock(mutex_);
  double t = clock_.seconds();
  if (!force && t - last_draw_ < 0.1) return;
  last_draw_ = t;
  double f = std::clamp(done_.load() / total_, 0.0, 1.0);
  double eta = f > 0.001 ? t * (1.0 - f) / f : 0.0;
  std::fprintf(stderr, "\r\033[K%s  %3.0f%%  ETA %.0fs", label_.c_str(), f * 100.0, eta);
  std::fflush(stderr);
}

void Progress::finish() {
  finished_ = true;
  if (terminal()) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s: done in %.2fs\n", label_.c_str(), clock_.seconds());
}

}  // namespace cumulo
