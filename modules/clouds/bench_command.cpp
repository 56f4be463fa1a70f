#include "modules/clouds/bench_command.h"

#include <algorithm>
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
  std::map<std::string, double> passes;  // median ms
};

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

bool is_cloud_pass(const std::string& name) {
  return name.rfind("clouds.", 0) == 0 && name != render::CloudFeature::kStepsReadbackPass;
}

std::string markdown(const std::vector<Run>& runs) {
  std::string t =
      "| view | ablation | mode | cloud ms | vs base | geometry ms | frame ms | steps/px | cloud passes (median ms) |\n"
      "|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& r : runs) {
    double base = 0;
    for (const Run& b : runs)
      if (b.view == r.view && b.mode == r.mode && b.ablation == CloudAblation::Base) base = b.cloud_ms;
    std::string passes;
    for (auto& [name, ms] : r.passes)
      if (is_cloud_pass(name)) passes += strf("%s%s %.2f", passes.empty() ? "" : ", ", name.c_str() + 7, ms);
    t += strf("| %s | %s | %d Hz | %.2f | %s | %.2f | %.2f | %.1f | %s |\n", r.view.c_str(),
              render::ablation_name(r.ablation), r.mode, r.cloud_ms,
              base > 0 && r.cloud_ms > 0 ? strf("%.2fx faster", base / r.cloud_ms).c_str() : "-", r.geometry_ms,
              r.frame_ms, r.steps_per_pixel, passes.c_str());
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
  std::vector<Run> runs;
  nlohmann::ordered_json memory = nlohmann::ordered_json::object();
  {
    cumulo::render::FrameRenderer renderer(ctx);
    renderer.add_feature(module);
    if (!feature.resources()) fail("%s: the level has no Cloudscape entity to measure", o.level.c_str());
    feature.set_measure_steps(true);
    app::OffscreenOutput output(ctx, o.width, o.height);
    gpu::FrameRing ring(ctx, 1);
    uint64_t frame_index = 0;
    const size_t total = o.views.size() * o.modes.size() * o.ablations.size();
    for (const std::string& view : o.views) {
      const ecs::Entity camera = sim.camera(view);
      for (int mode : o.modes) {
        for (CloudAblation ablation : o.ablations) {
          feature.options().ablation = ablation;
          Run run{view, ablation, mode};
          std::vector<double> cloud, geometry, whole, steps;
          std::map<std::string, std::vector<double>> passes;
          for (uint32_t f = 0; f < o.warmup + o.frames; ++f) {
            sim.extract();
            cumulo::render::FrameSnapshot s = cumulo::render::extract_frame(sim.world(), camera, o.width, o.height);
            module.extract(sim.world(), s);
            s.mode = cumulo::render::BudgetMode(mode);
            s.frame_index = ++frame_index;
            gpu::Frame& fr = ring.begin();
            renderer.record_frame(fr.cmd, s, output.target(), fr.slot);
            ring.submit(fr);
            ring.wait_all();
            output.after_frame();
            if (f < o.warmup) continue;
            double c = 0, g = 0, w = 0;
            for (auto& [name, ms] : renderer.pass_timings()) {
              if (name == render::CloudFeature::kStepsReadbackPass) continue;
              passes[name].push_back(ms);
              w += ms;
              if (is_cloud_pass(name)) c += ms;
              if (name == "geometry") g += ms;
            }
            cloud.push_back(c);
            geometry.push_back(g);
            whole.push_back(w);
            steps.push_back(feature.read_steps_per_pixel());
          }
          run.cloud_ms = median(cloud);
          run.geometry_ms = median(geometry);
          run.frame_ms = median(whole);
          run.steps_per_pixel = median(steps);
          for (auto& [name, v] : passes) run.passes[name] = median(v);
          runs.push_back(run);
          std::fprintf(stderr, "cumulo bench: [%zu/%zu] %s %s %d Hz: clouds %.2f ms, frame %.2f ms, %.1f steps/px\n",
                       runs.size(), total, view.c_str(), render::ablation_name(ablation), mode, run.cloud_ms,
                       run.frame_ms, run.steps_per_pixel);
        }
      }
    }
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

  std::printf("## cumulo bench: %s, %ux%u, %u frames per run (median, after %u warm-up frames)\n\n",
              ctx.info().name.c_str(), o.width, o.height, o.frames, o.warmup);
  std::printf("%s\n", markdown(runs).c_str());
  std::printf("GPU memory (bytes):\n");
  for (auto& [k, v] : memory.items()) std::printf("  %-40s %12llu\n", k.c_str(), (unsigned long long)v.get<uint64_t>());

  if (!o.out.empty()) {
    nlohmann::ordered_json j;
    j["device"] = {{"name", ctx.info().name}, {"driver", ctx.info().driver_name}, {"driver_info", ctx.info().driver_info}};
    j["size"] = {o.width, o.height};
    j["frames"] = o.frames;
    j["warmup_frames"] = o.warmup;
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
                      {"frame_ms", r.frame_ms},
                      {"steps_per_pixel", r.steps_per_pixel},
                      {"passes", p}});
    }
    j["runs"] = list;
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
