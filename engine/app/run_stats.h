#pragma once
// Statistics of a run, written by `cumulo run --stats PATH` as JSON:
//   { "frames", "size": [w, h], "mode", "sim_hz", "seed", "device": {name, driver, api},
//     "validation_enabled", "validation_errors" (null when validation was off), "peak_gpu_memory_bytes",
//     "cpu_frame_ms": {mean, min, max, median}, "gpu_frame_ms": {mean, min, max, median},
//     "budget": {frame_ms, scale, dynamic_resolution},
//     "resolution_scale": {mean, min, max, median, last, changes}   (the scaled passes' scale per frame),
//     "passes": { "<pass>": {mean_ms, min_ms, max_ms, median_ms, frames}, ... } }   (passes in frame order)
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace cumulo::app {

// Mean, min, max and median of a series (the median resists lavapipe's first-frame shader JIT and its
// rare 3x outliers: LAVAPIPE.md says quote medians).
struct MinMaxMean {
  double sum = 0, min = 0, max = 0;
  uint64_t count = 0;
  std::vector<double> samples;
  void add(double v);
  double mean() const { return count ? sum / static_cast<double>(count) : 0.0; }
  double median() const;
};

class RunStats {
 public:
  void add_cpu_frame_ms(double ms) { cpu_.add(ms); }
  // One frame's GPU pass timings (name, ms) in execution order.
  void add_gpu_frame(const std::vector<std::pair<std::string, double>>& passes);
  void set_frames(uint64_t frames) { frames_ = frames; }
  void add_resolution_scale(float s) { scale_.add(s); }

  struct Info {
    uint32_t width = 0, height = 0;
    int mode_hz = 30;
    uint32_t sim_hz = 60;
    uint64_t seed = 0;
    double sim_seconds = 0;
    std::string level, camera;
    std::string device_name, driver_name, driver_info, api_version;
    bool validation_enabled = false;                          // validation layers on (CUMULO_VALIDATION=1)
    uint64_t validation_errors = 0, validation_warnings = 0;  // written as null when validation was off
    uint64_t peak_gpu_memory_bytes = 0;
    bool dynamic_resolution = false;  // render/dynamic_resolution.h
    double frame_budget_ms = 0, budget_scale = 1;
    uint32_t resolution_changes = 0;
  };
  // The JSON text (pretty, keys in a stable order).
  std::string to_json(const Info& info) const;

  uint64_t frames() const { return frames_; }
  const MinMaxMean& cpu() const { return cpu_; }
  const std::vector<std::pair<std::string, MinMaxMean>>& passes() const { return passes_; }

 private:
  uint64_t frames_ = 0;
  MinMaxMean cpu_, gpu_total_, scale_;
  std::vector<std::pair<std::string, MinMaxMean>> passes_;  // frame order of first appearance
};

}  // namespace cumulo::app
