#include "modules/clouds/bench_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/app/frame_output.h"
#include "engine/app/run_options.h"
#include "engine/app/simulation.h"
#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/readback.h"
#include "engine/render/frame_renderer.h"
#include "modules/clouds/clouds_module.h"

namespace cumulo::clouds {
namespace {

using render::CloudAblation;

struct BenchOptions {
  std::string level = (repo_root() / "content/levels/sample/level.json").string();
  uint32_t width = 320, height = 180;
  uint32_t frames = 6;  // measured frames per run, after the warm-up
  uint32_t warmup = 3;  // lavapipe JITs on first use; the light grid is rebuilt whole on the first frame
  // The whole matrix is run this many times in turn and each run's samples pooled: a CPU device's speed
  // drifts over a minute (other work, clocks), and interleaving keeps the ratios within one run fair.
  uint32_t rounds = 3;
  std::string out;
  std::vector<std::string> views{"ground", "mixed", "immersed"};
  std::vector<CloudAblation> ablations{CloudAblation::Base, CloudAblation::VoxelLighting, CloudAblation::Full};
  std::vector<int> modes{30, 60};
};

struct Run {
  std::string view;
  CloudAblation ablation = CloudAblation::Full;
  int mode = 30;
  double cloud_ms = 0, geometry_ms = 0, frame_ms = 0, steps_per_pixel = 0;
  double sky_ms = 0;  // the 2.5D sky and the light shafts (is_sky_pass)
  std::map<std::string, double> passes;  // median ms
  double psnr_vs_30hz_db = 0;  // 60 Hz runs: the final image against the 30 Hz run's (tonemapped, 8-bit)
  // Samples pooled over the rounds, and the last round's final image.
  std::vector<double> cloud, geometry, whole, steps, sky;
  std::map<std::string, std::vector<double>> pass_samples;
  gpu::Rgba8Image image;
};

// PSNR of two 8-bit RGBA images over RGB (dB; 99 when identical).
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

// Per view, the figures the targets name (each needs its runs in the matrix; NAN otherwise).
struct Summary {
  std::string view;
  double full_vs_base_30 = NAN, full_vs_base_60 = NAN;  // base cloud ms / full cloud ms
  double split_saving = NAN;                            // 1 - full 60 Hz / full 30 Hz cloud ms
  double split_psnr_db = NAN;                           // full 60 Hz image vs full 30 Hz
  double light_grid_share_30 = NAN, light_grid_share_60 = NAN;  // light grid ms / cloud ms (full, sun still)
  double light_grid_moving_30 = NAN, light_grid_moving_60 = NAN;  // the same with the grid updating every frame
  double fps_60 = NAN;                                  // 1000 / frame ms, full 60 Hz
};
std::vector<Summary> summarize(const std::vector<Run>& runs, const std::vector<Run>& moving,
                               const std::vector<std::string>& views) {
  std::vector<Summary> out;
  auto grid_share = [](const Run* r) {
    if (!r || r->cloud_ms <= 0) return double(NAN);
    auto it = r->passes.find("clouds.light_grid");
    return it == r->passes.end() ? 0.0 : it->second / r->cloud_ms;  // absent: the grid rested
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
    out.push_back(s);
  }
  return out;
}

std::string summary_markdown(const std::vector<Summary>& sums) {
  auto num = [](double v, const char* fmt) { return std::isnan(v) ? std::string("-") : strf(fmt, v); };
  std::string t =
      "| view | full vs base 30 Hz | full vs base 60 Hz | 60 Hz split saves | split PSNR vs 30 Hz | light grid share 30 / 60 Hz "
      "(sun still) | light grid share 30 / 60 Hz (updating every frame) | fps (full, 60 Hz) |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const Summary& s : sums)
    t += strf("| %s | %s | %s | %s | %s | %s / %s | %s / %s | %s |\n", s.view.c_str(),
              num(s.full_vs_base_30, "%.2fx").c_str(), num(s.full_vs_base_60, "%.2fx").c_str(),
              num(100.0 * s.split_saving, "%.0f %%").c_str(), num(s.split_psnr_db, "%.1f dB").c_str(),
              num(100.0 * s.light_grid_share_30, "%.1f %%").c_str(), num(100.0 * s.light_grid_share_60, "%.1f %%").c_str(),
              num(100.0 * s.light_grid_moving_30, "%.1f %%").c_str(), num(100.0 * s.light_grid_moving_60, "%.1f %%").c_str(),
              num(s.fps_60, "%.1f").c_str());
  return t;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// The world-facing passes of issue 10 (the 2.5D sky, light shafts): the same in every ablation, so they
// are timed on their own and kept out of the voxel clouds' time (whose ablation ratios they would dilute).
bool is_sky_pass(const std::string& name) {
  return name.rfind("clouds.sky_layer", 0) == 0 || name.rfind("clouds.light_shafts", 0) == 0;
}
bool is_cloud_pass(const std::string& name) {
  return name.rfind("clouds.", 0) == 0 && name != render::CloudFeature::kStepsReadbackPass && !is_sky_pass(name);
}

std::string markdown(const std::vector<Run>& runs) {
  std::string t =
      "| view | ablation | mode | cloud ms | vs base | geometry ms | 2.5D sky + shafts ms | frame ms | steps/px | cloud passes (median ms) |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& r : runs) {
    double base = 0;
    for (const Run& b : runs)
      if (b.view == r.view && b.mode == r.mode && b.ablation == CloudAblation::Base) base = b.cloud_ms;
    std::string passes;
    for (auto& [name, ms] : r.passes)
      if (is_cloud_pass(name) || is_sky_pass(name))
        passes += strf("%s%s %.2f", passes.empty() ? "" : ", ", name.c_str() + 7, ms);
    t += strf("| %s | %s | %d Hz | %.2f | %s | %.2f | %.2f | %.2f | %.1f | %s |\n", r.view.c_str(),
              render::ablation_name(r.ablation), r.mode, r.cloud_ms,
              base > 0 && r.cloud_ms > 0 ? strf("%.2fx faster", base / r.cloud_ms).c_str() : "-", r.geometry_ms,
              r.sky_ms, r.frame_ms, r.steps_per_pixel, passes.c_str());
  }
  return t;
}

int run_bench(const BenchOptions& o, CloudsModule& module) {
  render::CloudFeature& feature = module.feature();
  auto modules = app::Modules{std::shared_ptr<app::Module>(&module, [](app::Module*) {})};
  app::SimulationDesc sd;
  sd.level = o.level;
  sd.modules = modules;
  app::Simulation sim(sd);

  gpu::Context ctx(gpu::ContextDesc{});
  LOG_INFO("device: %s (%s)", ctx.info().name.c_str(), ctx.info().driver_info.c_str());
  std::vector<Run> runs, moving;  // moving: full runs with the light grid updating every frame
  nlohmann::ordered_json memory = nlohmann::ordered_json::object();
  {
    cumulo::render::FrameRenderer renderer(ctx);
    renderer.add_feature(module);
    if (!feature.resources()) fail("%s: the level has no Cloudscape entity to measure", o.level.c_str());
    feature.set_measure_steps(true);
    app::OffscreenOutput output(ctx, o.width, o.height);
    gpu::FrameRing ring(ctx, 1);
    uint64_t frame_index = 0;
    const size_t configs = o.views.size() * o.modes.size() * o.ablations.size();
    for (const std::string& view : o.views)
      for (int mode : o.modes)
        for (CloudAblation ablation : o.ablations) runs.push_back(Run{view, ablation, mode});
    // The sample level's sun is still, so the light grid rests once built (light_grid_sweep.comp); these
    // runs keep its updates going (as a moving sun does) to measure what they cost: full, every mode.
    if (std::find(o.ablations.begin(), o.ablations.end(), CloudAblation::Full) != o.ablations.end())
      for (const std::string& view : o.views)
        for (int mode : o.modes) moving.push_back(Run{view, CloudAblation::Full, mode});
    const size_t total = (configs + moving.size()) * o.rounds;
    size_t done = 0;
    for (uint32_t round = 0; round < o.rounds; ++round) {
      for (size_t index = 0; index < runs.size() + moving.size(); ++index) {
        const bool sun_moving = index >= runs.size();
        Run& run = sun_moving ? moving[index - runs.size()] : runs[index];
        feature.options().light_grid_always_update = sun_moving;
        const ecs::Entity camera = sim.camera(run.view);
        feature.options().ablation = run.ablation;
        for (uint32_t f = 0; f < o.warmup + o.frames; ++f) {
          sim.extract();
          cumulo::render::FrameSnapshot s = cumulo::render::extract_frame(sim.world(), camera, o.width, o.height);
          module.extract(sim.world(), s);
          s.mode = cumulo::render::BudgetMode(run.mode);
          s.frame_index = ++frame_index;
          gpu::Frame& fr = ring.begin();
          renderer.record_frame(fr.cmd, s, output.target(), fr.slot);
          ring.submit(fr);
          ring.wait_all();
          output.after_frame();
          if (f < o.warmup) continue;
          double c = 0, g = 0, w = 0, k = 0;
          for (auto& [name, ms] : renderer.pass_timings()) {
            if (name == render::CloudFeature::kStepsReadbackPass) continue;
            run.pass_samples[name].push_back(ms);
            w += ms;
            if (is_cloud_pass(name)) c += ms;
            if (is_sky_pass(name)) k += ms;
            if (name == "geometry") g += ms;
          }
          run.cloud.push_back(c);
          run.sky.push_back(k);
          run.geometry.push_back(g);
          run.whole.push_back(w);
          run.steps.push_back(feature.read_steps_per_pixel());
        }
        if (round + 1 == o.rounds && !sun_moving) run.image = gpu::read_image_rgba8(ctx, output.image());
        std::fprintf(stderr, "cumulo bench: [%zu/%zu] %s %s%s %d Hz: clouds %.2f ms, frame %.2f ms, %.1f steps/px\n",
                     ++done, total, run.view.c_str(), render::ablation_name(run.ablation),
                     sun_moving ? " (light grid updating)" : "", run.mode, median(run.cloud), median(run.whole),
                     median(run.steps));
      }
    }
    feature.options().light_grid_always_update = false;
    for (std::vector<Run>* list : {&runs, &moving})
      for (Run& run : *list) {
        run.cloud_ms = median(run.cloud);
        run.sky_ms = median(run.sky);
        run.geometry_ms = median(run.geometry);
        run.frame_ms = median(run.whole);
        run.steps_per_pixel = median(run.steps);
        for (auto& [name, v] : run.pass_samples) run.passes[name] = median(v);
      }
    for (Run& run : runs)
      if (run.mode != 30)
        if (const Run* r30 = find_run(runs, run.view, run.ablation, 30)) run.psnr_vs_30hz_db = psnr_rgb(r30->image, run.image);
    // Memory: the loaded set, and both format sets of the cloudscape for the talk's budget.
    render::CloudAssetCache& cache = *feature.asset_cache();
    cumulo::render::FrameSnapshot s = cumulo::render::extract_frame(sim.world(), sim.camera(o.views.front()), 1, 1);
    module.extract(sim.world(), s);
    const auto& frame = s.extensions.get<render::CloudFrame>();
    for (auto set : {render::CloudFormatSet::Compressed, render::CloudFormatSet::Uncompressed}) {
      auto asset = cache.cloudscape(frame.instances.front().folder, render::CloudFormats::from_set(set));
      memory[std::string("cloudscape_") + render::format_set_name(set)] = asset->gpu_bytes;
    }
    memory["light_grids_and_history"] = render::persistent_gpu_bytes(*feature.resources());
    memory["all_cloud_assets_loaded"] = cache.gpu_bytes();
    ctx.wait_idle();
  }

  std::printf("## cumulo bench: %s, %ux%u, %u frames per run x %u rounds (median, after %u warm-up frames)\n\n",
              ctx.info().name.c_str(), o.width, o.height, o.frames, o.rounds, o.warmup);
  std::printf("%s\n", markdown(runs).c_str());
  const std::vector<Summary> sums = summarize(runs, moving, o.views);
  std::printf("Targets (issue 8: full vs base >= 4.5x / 3x / 2.5x ground / mixed / immersed; the 60 Hz split >= 45 %% "
              "cheaper at >= 35 dB; light grid < 5 %%; 20 fps at 320x180 on lavapipe):\n\n%s\n",
              summary_markdown(sums).c_str());
  std::printf("GPU memory (bytes):\n");
  for (auto& [k, v] : memory.items()) std::printf("  %-40s %12llu\n", k.c_str(), (unsigned long long)v.get<uint64_t>());

  if (!o.out.empty()) {
    nlohmann::ordered_json j;
    j["device"] = {{"name", ctx.info().name}, {"driver", ctx.info().driver_name}, {"driver_info", ctx.info().driver_info}};
    j["size"] = {o.width, o.height};
    j["frames"] = o.frames;
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
                      {"frame_ms", r.frame_ms},
                      {"steps_per_pixel", r.steps_per_pixel},
                      {"passes", p}});
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
                         {"fps_60", num(su.fps_60)}});
    j["summary"] = summary;
    write_file_atomic(o.out, j.dump(2) + "\n");
    std::printf("cumulo bench: wrote %s\n", o.out.c_str());
  }
  if (ctx.validation_errors() > 0) {
    LOG_ERROR("%u Vulkan validation errors (last: %s)", ctx.validation_errors(), ctx.last_validation_message().c_str());
    return 3;
  }
  return 0;
}

}  // namespace

void register_bench_command(CommandRegistry& registry) {
  registry.add({"bench", "measure the cloud renderer: cameras x ablations x budget modes (table + JSON)", [](int argc, char** argv) {
                  BenchOptions o;
                  std::string size, views, ablations, modes;
                  CloudsModule module;
                  ArgParser p("cumulo bench",
                              "Measure the cloud renderer on this device: the level's cameras x the talk's ablation steps\n"
                              "(base, voxel-lighting, full) x budget modes (30: one march, 60: near/far split). Prints a\n"
                              "markdown table; --out writes JSON (device, size, frames, memory, runs).");
                  p.option("--level", "LEVEL", "level with a Cloudscape (default content/levels/sample/level.json)", &o.level)
                      .option("--size", "WxH", "render size (default 320x180; 960x540 on a GPU)", &size)
                      .option("--frames", "N", "measured frames per run (default 6)", &o.frames)
                      .option("--warmup", "N", "frames rendered before measuring (default 3)", &o.warmup)
                      .option("--rounds", "N", "times the whole matrix is run in turn, samples pooled (default 3)", &o.rounds)
                      .option("--out", "FILE.json", "write the results as JSON", &o.out)
                      .option("--views", "A,B", "cameras (default ground,mixed,immersed)", &views)
                      .option("--ablations", "A,B", "ablation steps (default base,voxel-lighting,full)", &ablations)
                      .option("--modes", "30,60", "budget modes (default 30,60)", &modes);
                  module.feature().add_run_options(p);  // --cloud-formats, --cloud-temporal, ...
                  if (!p.parse(argc, argv)) return 0;
                  module.feature().check_run_options();
                  if (!size.empty()) app::parse_size(size, o.width, o.height);
                  if (o.frames < 1 || o.frames > 1000) fail("--frames: %u is outside 1..1000", o.frames);
                  if (o.warmup > 100) fail("--warmup: %u is outside 0..100", o.warmup);
                  if (o.rounds < 1 || o.rounds > 100) fail("--rounds: %u is outside 1..100", o.rounds);
                  if (!views.empty()) o.views = split_list(views);
                  if (o.views.empty()) fail("--views: no camera named");
                  if (!ablations.empty()) {
                    o.ablations.clear();
                    for (const std::string& a : split_list(ablations)) {
                      CloudAblation v;
                      if (!render::parse_ablation(a, &v))
                        fail("--ablations: unknown \"%s\" (expected base, voxel-lighting, full)", a.c_str());
                      o.ablations.push_back(v);
                    }
                  }
                  if (!modes.empty()) {
                    o.modes.clear();
                    for (const std::string& m : split_list(modes))
                      o.modes.push_back(cumulo::render::budget_hz(cumulo::render::parse_budget_mode(m)));
                  }
                  return run_bench(o, module);
                }});
}

}  // namespace cumulo::clouds
