#include "modules/clouds/bench/bench_runs.h"

#include <algorithm>

#include "modules/clouds/render/cloud_feature.h"

namespace cumulo::clouds::bench {

double psnr_rgb(const gpu::Rgba8Image& a, const gpu::Rgba8Image& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.empty()) return 0.0;
  double se = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.pixels.size(); i += 4)
    for (int c = 0; c < 3; ++c, ++n) {
      const double d = double(a.pixels[i + c]) - double(b.pixels[i + c]);
      se += d * d;
    }
  const double mse = se / double(n);
  return mse <= 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

const Run* find_run(const std::vector<Run>& runs, const std::string& view, CloudAblation a, int mode) {
  for (const Run& r : runs)
    if (r.view == view && r.ablation == a && r.mode == mode) return &r;
  return nullptr;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool is_sky_layer_pass(const std::string& name) { return name.rfind("clouds.sky_layer", 0) == 0; }
bool is_shafts_pass(const std::string& name) { return name.rfind("clouds.light_shafts", 0) == 0; }
bool is_sky_pass(const std::string& name) { return is_sky_layer_pass(name) || is_shafts_pass(name); }
bool is_envelope_pass(const std::string& name) { return name.rfind("clouds.envelope", 0) == 0; }
bool is_cloud_pass(const std::string& name) {
  return name.rfind("clouds.", 0) == 0 && name != render::CloudFeature::kStepsReadbackPass && !is_sky_pass(name) &&
         !is_envelope_pass(name);
}

void finish_runs(std::vector<Run>& runs, std::vector<Run>& moving) {
  for (std::vector<Run>* list : {&runs, &moving})
    for (Run& run : *list) {
      run.cloud_ms = median(run.cloud);
      run.sky_ms = median(run.sky);
      run.geometry_ms = median(run.geometry);
      run.frame_ms = median(run.whole);
      run.wall_ms = median(run.wall);
      run.cpu_ms = median(run.cpu);
      run.steps_per_pixel = median(run.steps);
      for (auto& [name, v] : run.pass_samples) run.passes[name] = median(v);
      for (auto& [name, ms] : run.passes) {
        if (is_sky_layer_pass(name)) run.sky_layer_ms += ms;
        if (is_shafts_pass(name)) run.shafts_ms += ms;
        if (is_envelope_pass(name)) run.envelope_ms += ms;
      }
    }
  for (Run& run : runs)
    if (run.mode != 30)
      if (const Run* r30 = find_run(runs, run.view, run.ablation, 30)) run.psnr_vs_30hz_db = psnr_rgb(r30->image, run.image);
}

std::vector<Summary> summarize(const std::vector<Run>& runs, const std::vector<Run>& moving,
                               const std::vector<std::string>& views) {
  std::vector<Summary> out;
  auto grid_share = [](const Run* r) {
    if (!r || r->cloud_ms <= 0) return double(NAN);
    // The grid and what the march reads of it (clouds.light_grid_local); absent: the grid rested.
    double ms = 0.0;
    for (const char* name : {"clouds.light_grid", "clouds.light_grid_local"})
      if (auto it = r->passes.find(name); it != r->passes.end()) ms += it->second;
    return ms / r->cloud_ms;
  };
  for (const std::string& v : views) {
    Summary s{v};
    const Run* f30 = find_run(runs, v, CloudAblation::Full, 30);
    const Run* f60 = find_run(runs, v, CloudAblation::Full, 60);
    const Run* b30 = find_run(runs, v, CloudAblation::Base, 30);
    const Run* b60 = find_run(runs, v, CloudAblation::Base, 60);
    if (f30 && b30 && f30->cloud_ms > 0) s.full_vs_base_30 = b30->cloud_ms / f30->cloud_ms;
    if (f60 && b60 && f60->cloud_ms > 0) s.full_vs_base_60 = b60->cloud_ms / f60->cloud_ms;
    if (f30 && f60 && f30->cloud_ms > 0) {
      s.split_saving = 1.0 - f60->cloud_ms / f30->cloud_ms;
      s.split_psnr_db = f60->psnr_vs_30hz_db;
    }
    s.light_grid_share_30 = grid_share(f30);
    s.light_grid_share_60 = grid_share(f60);
    s.light_grid_moving_30 = grid_share(find_run(moving, v, CloudAblation::Full, 30));
    s.light_grid_moving_60 = grid_share(find_run(moving, v, CloudAblation::Full, 60));
    if (f60 && f60->frame_ms > 0) s.fps_60 = 1000.0 / f60->frame_ms;
    if (f60 && f60->wall_ms > 0) s.fps_wall_60 = 1000.0 / f60->wall_ms;
    if (f60) s.cpu_ms_60 = f60->cpu_ms;
    for (size_t r = 0; f30 && b30 && r < std::min(f30->rounds.size(), b30->rounds.size()); ++r)
      if (f30->rounds[r].cloud_ms > 0) s.full_vs_base_30_rounds.push_back(b30->rounds[r].cloud_ms / f30->rounds[r].cloud_ms);
    for (size_t r = 0; f30 && f60 && r < std::min(f30->rounds.size(), f60->rounds.size()); ++r)
      if (f30->rounds[r].cloud_ms > 0) s.split_saving_rounds.push_back(1.0 - f60->rounds[r].cloud_ms / f30->rounds[r].cloud_ms);
    out.push_back(s);
  }
  return out;
}

}  // namespace cumulo::clouds::bench
