#include "engine/app/run_stats.h"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace cumulo::app {

void MinMaxMean::add(double v) {
  if (count == 0) {
    min = max = v;
  } else {
    min = std::min(min, v);
    max = std::max(max, v);
  }
  sum += v;
  ++count;
  samples.push_back(v);
}

double MinMaxMean::median() const {
  if (samples.empty()) return 0.0;
  std::vector<double> s = samples;
  size_t mid = s.size() / 2;
  std::nth_element(s.begin(), s.begin() + long(mid), s.end());
  if (s.size() % 2) return s[mid];
  double hi = s[mid];
  double lo = *std::max_element(s.begin(), s.begin() + long(mid));
  return 0.5 * (lo + hi);
}

void RunStats::add_gpu_frame(const std::vector<std::pair<std::string, double>>& passes) {
  if (passes.empty()) return;
  double total = 0;
  for (auto& [name, ms] : passes) {
    auto it = std::find_if(passes_.begin(), passes_.end(), [&](auto& p) { return p.first == name; });
    if (it == passes_.end()) {
      passes_.emplace_back(name, MinMaxMean{});
      it = passes_.end() - 1;
    }
    it->second.add(ms);
    total += ms;
  }
  gpu_total_.add(total);
}

std::string RunStats::to_json(const Info& in) const {
  using J = nlohmann::ordered_json;
  auto stat = [](const MinMaxMean& s) { return J{{"mean", s.mean()}, {"min", s.min}, {"max", s.max}, {"median", s.median()}}; };
  J j;
  j["frames"] = frames_;
  j["size"] = {in.width, in.height};
  j["mode"] = in.mode_hz;
  j["sim_hz"] = in.sim_hz;
  j["seed"] = in.seed;
  j["sim_seconds"] = in.sim_seconds;
  j["level"] = in.level;
  j["camera"] = in.camera;
  j["device"] = {{"name", in.device_name}, {"driver", in.driver_name}, {"driver_info", in.driver_info}, {"api", in.api_version}};
  // Without the layers nothing was checked: say so rather than report a reassuring 0.
  j["validation_enabled"] = in.validation_enabled;
  j["validation_errors"] = in.validation_enabled ? J(in.validation_errors) : J(nullptr);
  j["validation_warnings"] = in.validation_enabled ? J(in.validation_warnings) : J(nullptr);
  j["peak_gpu_memory_bytes"] = in.peak_gpu_memory_bytes;
  j["cpu_frame_ms"] = stat(cpu_);
  j["gpu_frame_ms"] = stat(gpu_total_);
  j["budget"] = {{"frame_ms", in.frame_budget_ms}, {"scale", in.budget_scale}, {"dynamic_resolution", in.dynamic_resolution}};
  J scale = stat(scale_);
  scale["last"] = scale_.samples.empty() ? 1.0 : scale_.samples.back();
  scale["changes"] = in.resolution_changes;
  j["resolution_scale"] = scale;
  J passes = J::object();
  for (auto& [name, s] : passes_)
    passes[name] = {{"mean_ms", s.mean()}, {"min_ms", s.min}, {"max_ms", s.max}, {"median_ms", s.median()}, {"frames", s.count}};
  j["passes"] = passes;
  return j.dump(2) + "\n";
}

}  // namespace cumulo::app
