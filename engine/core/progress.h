#pragma once
// A progress line for long work (bakes, noise, imports): "label  42%  ETA 12s" redrawn in place on a
// terminal, silent when stderr is not a terminal (CI logs), with a final summary line either way.
// update() is thread-safe and rate-limited, so workers may call it freely.
#include <atomic>
#include <mutex>
#include <string>

#include "engine/core/time.h"

namespace cumulo {

class Progress {
 public:
  Progress(std::string label, double total);
  ~Progress();
  void add(double amount);     // thread-safe
  void set(double done);       // thread-safe
  void finish();               // prints "label done in 3.2s"
  static bool terminal();      // stderr is a TTY and CUMULO_PROGRESS != 0

 private:
  void draw(bool force);
  std::string label_;
  double total_;
  std::atomic<double> done_{0.0};
  Stopwatch clock_;
  double last_draw_ = -1.0;
  bool finished_ = false;
  std::mutex mutex_;
};

}  // namespace cumulo
