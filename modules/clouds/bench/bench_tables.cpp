#include "modules/clouds/bench/bench_tables.h"

#include <algorithm>

#include "engine/core/error.h"

namespace cumulo::clouds::bench {

std::string runs_markdown(const std::vector<Run>& runs) {
  std::string t =
      "| view | ablation | mode | cloud ms | vs base | geometry ms | 2.5D sky ms | shafts ms | envelope ms | GPU sum ms | wall ms | CPU ms | steps/px | cloud passes (median ms) |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& r : runs) {
    double base = 0;
    for (const Run& b : runs)
      if (b.view == r.view && b.mode == r.mode && b.ablation == CloudAblation::Base) base = b.cloud_ms;
    std::string passes;
    for (auto& [name, ms] : r.passes)
      if (is_cloud_pass(name) || is_sky_pass(name) || is_envelope_pass(name))
        passes += strf("%s%s %.2f", passes.empty() ? "" : ", ", name.c_str() + 7, ms);
    t += strf("| %s | %s | %d Hz | %.2f | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %s |\n", r.view.c_str(),
              render::ablation_name(r.ablation), r.mode, r.cloud_ms,
              base > 0 && r.cloud_ms > 0 ? strf("%.2fx faster", base / r.cloud_ms).c_str() : "-", r.geometry_ms,
              r.sky_layer_ms, r.shafts_ms, r.envelope_ms, r.frame_ms, r.wall_ms, r.cpu_ms, r.steps_per_pixel, passes.c_str());
  }
  return t;
}

std::string summary_markdown(const std::vector<Summary>& sums) {
  auto num = [](double v, const char* fmt) { return std::isnan(v) ? std::string("-") : strf(fmt, v); };
  auto least = [](const std::vector<double>& v) { return v.empty() ? double(NAN) : *std::min_element(v.begin(), v.end()); };
  std::string t =
      "| view | full vs base 30 Hz | (worst round) | full vs base 60 Hz | 60 Hz split saves | (worst round) | split PSNR vs 30 Hz | "
      "light grid share 30 / 60 Hz (sun still) | light grid share 30 / 60 Hz (updating every frame) | fps wall (full, 60 Hz) | "
      "fps GPU sum | CPU ms |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Summary& s : sums)
    t += strf("| %s | %s | %s | %s | %s | %s | %s | %s / %s | %s / %s | %s | %s | %s |\n", s.view.c_str(),
              num(s.full_vs_base_30, "%.2fx").c_str(), num(least(s.full_vs_base_30_rounds), "%.2fx").c_str(),
              num(s.full_vs_base_60, "%.2fx").c_str(), num(100.0 * s.split_saving, "%.0f %%").c_str(),
              num(100.0 * least(s.split_saving_rounds), "%.0f %%").c_str(), num(s.split_psnr_db, "%.1f dB").c_str(),
              num(100.0 * s.light_grid_share_30, "%.1f %%").c_str(), num(100.0 * s.light_grid_share_60, "%.1f %%").c_str(),
              num(100.0 * s.light_grid_moving_30, "%.1f %%").c_str(), num(100.0 * s.light_grid_moving_60, "%.1f %%").c_str(),
              num(s.fps_wall_60, "%.1f").c_str(), num(s.fps_60, "%.1f").c_str(), num(s.cpu_ms_60, "%.2f").c_str());
  return t;
}

nlohmann::ordered_json bench_json(const BenchOptions& o, const gpu::DeviceInfo& device, const nlohmann::ordered_json& memory,
                                  const std::vector<Run>& runs, const std::vector<Summary>& sums) {
  nlohmann::ordered_json j;
  j["device"] = {{"name", device.name}, {"driver", device.driver_name}, {"driver_info", device.driver_info}};
  j["size"] = {o.width, o.height};
  j["frames"] = o.frames;
  j["frames_full_method"] = measured_frames(o, CloudAblation::Full);
  j["warmup_frames"] = o.warmup;
  j["rounds"] = o.rounds;
  j["memory"] = memory;
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const Run& r : runs) {
    nlohmann::ordered_json p = nlohmann::ordered_json::object();
    for (auto& [name, ms] : r.passes) p[name] = ms;
    list.push_back({{"view", r.view},
                    {"ablation", render::ablation_name(r.ablation)},
                    {"mode", r.mode},
                    {"cloud_ms", r.cloud_ms},
                    {"geometry_ms", r.geometry_ms},
                    {"sky_layer_and_shafts_ms", r.sky_ms},
                    {"sky_layer_ms", r.sky_layer_ms},
                    {"envelope_ms", r.envelope_ms},
                    {"light_shafts_ms", r.shafts_ms},
                    {"frame_ms", r.frame_ms},
                    {"wall_ms", r.wall_ms},
                    {"cpu_ms", r.cpu_ms},
                    {"steps_per_pixel", r.steps_per_pixel},
                    {"passes", p}});
    nlohmann::ordered_json rounds = nlohmann::ordered_json::array();
    for (const RoundFigures& f : r.rounds)
      rounds.push_back({{"cloud_ms", f.cloud_ms}, {"geometry_ms", f.geometry_ms}, {"sky_layer_and_shafts_ms", f.sky_ms},
                        {"frame_ms", f.frame_ms}, {"wall_ms", f.wall_ms}, {"cpu_ms", f.cpu_ms}});
    list.back()["rounds"] = rounds;
    if (r.mode != 30 && r.psnr_vs_30hz_db > 0) list.back()["psnr_vs_30hz_db"] = r.psnr_vs_30hz_db;
  }
  j["runs"] = list;
  auto num = [](double v) { return std::isnan(v) ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v); };
  nlohmann::ordered_json summary = nlohmann::ordered_json::array();
  for (const Summary& su : sums)
    summary.push_back({{"view", su.view},
                       {"full_vs_base_30", num(su.full_vs_base_30)},
                       {"full_vs_base_60", num(su.full_vs_base_60)},
                       {"split_saving", num(su.split_saving)},
                       {"split_psnr_db", num(su.split_psnr_db)},
                       {"light_grid_share_30", num(su.light_grid_share_30)},
                       {"light_grid_share_60", num(su.light_grid_share_60)},
                       {"light_grid_share_updating_30", num(su.light_grid_moving_30)},
                       {"light_grid_share_updating_60", num(su.light_grid_moving_60)},
                       {"fps_60", num(su.fps_60)},
                       {"fps_wall_60", num(su.fps_wall_60)},
                       {"cpu_ms_60", num(su.cpu_ms_60)},
                       {"full_vs_base_30_rounds", su.full_vs_base_30_rounds},
                       {"split_saving_rounds", su.split_saving_rounds}});
  j["summary"] = summary;
  return j;
}

}  // namespace cumulo::clouds::bench
