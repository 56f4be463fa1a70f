#include "modules/clouds/bench/bench_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "engine/app/headless_session.h"
#include "engine/app/run_options.h"
#include "engine/app/simulation.h"
#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/gpu/readback.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/render/frame_renderer.h"
#include "modules/clouds/bench/bench_growth.h"
#include "modules/clouds/bench/bench_runs.h"
#include "modules/clouds/bench/bench_tables.h"

namespace cumulo::clouds {
namespace {

using namespace bench;

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

// Frames rendered before a run's image is kept: the full method's, its reprojection cycled four times
// (render::reprojection_block's largest block is 4, 16 frames a cycle) and its temporal accumulation (a new frame's
// weight 0.1) converged on the pixels marched last (issue 23: at 16 frames the 60 Hz image, whose 1-in-16 pixels
// had each been marched once, still held a third of its first frames' upsampling: ground 31.4 dB from the 30 Hz
// image, 34.1 at 64); the base and voxel-lighting runs (a second or more a frame on a CPU device) one cycle.
constexpr uint32_t kConvergedFrames = 64;
constexpr uint32_t kConvergedFramesSlow = 16;

// A run's samples in one round (the chunks of its measured frames pooled).
struct RoundSamples {
  std::vector<double> cloud, sky, geometry, whole, wall, cpu;
};

// One chunk of a configuration's round: `warmup` frames, then `frames` measured ones: their pass timings and steps,
// and the headless loop's wall clock: the CPU part (extraction, render graph, recording, up to the submit) and the
// whole frame up to the GPU's finish.
void measure_chunk(app::HeadlessSession& session, render::CloudFeature& feature, Run& run, RoundSamples& round,
                   bool sun_moving, uint32_t warmup, uint32_t frames) {
  feature.options().light_grid_always_update = sun_moving;
  feature.options().ablation = run.ablation;
  const ecs::Entity camera = session.sim().camera(run.view);
  for (uint32_t f = 0; f < warmup + frames; ++f) {
    const Stopwatch frame;
    cumulo::render::FrameSnapshot snapshot = session.extract(camera, cumulo::render::BudgetMode(run.mode));
    session.submit(snapshot);
    const double cpu_ms = frame.ms();
    session.wait_frame();
    const double wall_ms = frame.ms();
    if (f < warmup) continue;
    double c = 0, g = 0, w = 0, k = 0;
    for (auto& [name, ms] : session.pass_timings()) {
      if (name == render::CloudFeature::kStepsReadbackPass) continue;
      run.pass_samples[name].push_back(ms);
      w += ms;
      if (is_cloud_pass(name)) c += ms;
      if (is_sky_pass(name)) k += ms;
      if (name == "geometry") g += ms;
    }
    round.cloud.push_back(c);
    round.sky.push_back(k);
    round.geometry.push_back(g);
    round.whole.push_back(w);
    round.cpu.push_back(cpu_ms);
    round.wall.push_back(wall_ms);
    run.steps.push_back(feature.read_steps_per_pixel());
  }
}

// A round's medians into the run's figures, its samples into the pooled ones.
void finish_round(Run& run, const RoundSamples& r) {
  run.rounds.push_back({median(r.cloud), median(r.sky), median(r.geometry), median(r.whole), median(r.wall), median(r.cpu)});
  using Samples = std::vector<double>;
  const std::pair<Samples*, const Samples*> pools[] = {{&run.cloud, &r.cloud}, {&run.sky, &r.sky}, {&run.geometry, &r.geometry},
                                                       {&run.whole, &r.whole}, {&run.wall, &r.wall}, {&run.cpu, &r.cpu}};
  for (auto [pooled, samples] : pools) pooled->insert(pooled->end(), samples->begin(), samples->end());
}

// The image the 60 Hz split's PSNR compares: converged, as a still camera shows it once the reprojection has
// marched every pixel of its block four times and the temporal accumulation has settled; rendered in one go after
// the round's chunks (a switch of mode starts a new history).
void keep_image(app::HeadlessSession& session, const BenchOptions& o, Run& run) {
  const ecs::Entity camera = session.sim().camera(run.view);
  const uint32_t converged = run.ablation == CloudAblation::Full ? kConvergedFrames : kConvergedFramesSlow;
  for (uint32_t f = 0; f < converged; ++f) {
    cumulo::render::FrameSnapshot snapshot = session.extract(camera, cumulo::render::BudgetMode(run.mode));
    session.render(snapshot);
  }
  run.image = session.screenshot();
  if (!o.images.empty()) {
    const std::string path = o.images + "/" + run.view + "_" + render::ablation_name(run.ablation) + "_" +
                             std::to_string(run.mode) + "hz.png";
    gpu::write_png(path, run.image);
  }
}

// GPU memory: the loaded set, and both format sets of the first cloudscape for the talk's budget.
nlohmann::ordered_json measure_memory(app::HeadlessSession& session, render::CloudFeature& feature, const BenchOptions& o) {
  nlohmann::ordered_json memory = nlohmann::ordered_json::object();
  render::CloudAssetCache& cache = *feature.asset_cache();
  const cumulo::render::FrameSnapshot s = session.extract(session.sim().camera(o.views.front()), cumulo::render::BudgetMode::Hz30);
  const auto& frame = s.extensions.get<CloudFrame>();
  for (auto set : {render::CloudFormatSet::Compressed, render::CloudFormatSet::Uncompressed}) {
    auto asset = cache.cloudscape(frame.instances.front().folder, render::CloudFormats::from_set(set));
    memory[std::string("cloudscape_") + render::format_set_name(set)] = asset->gpu_bytes;
  }
  memory["light_grids_and_history"] = render::persistent_gpu_bytes(*feature.resources());
  memory["all_cloud_assets_loaded"] = cache.gpu_bytes();
  return memory;
}

// The simulation's CPU ms per 60 Hz frame (the systems' fixed steps of 1/60 s), median of `frames`. Apart
// from the matrix, after it: the matrix renders a still scene, since a stepping one would change between the
// runs whose images and ratios it compares.
double measure_simulation(app::HeadlessSession& session, uint32_t frames) {
  app::Simulation& sim = session.sim();
  const uint64_t steps = std::max<uint64_t>(1, uint64_t(std::llround((1.0 / 60.0) / sim.step_seconds())));
  std::vector<double> ms;
  for (uint32_t f = 0; f < frames; ++f) {
    const Stopwatch step;
    sim.step(steps);
    ms.push_back(step.ms());
  }
  return median(ms);
}

void report(const BenchOptions& o, const gpu::DeviceInfo& device, const nlohmann::ordered_json& memory,
            const std::vector<Run>& runs, const std::vector<Run>& moving, double simulation_ms,
            const GrowthFigures* growth) {
  std::printf("## cumulo bench: %s, %ux%u, %u frames per run (the full method's %u) x %u rounds (median, after %u warm-up "
              "frames)\n\n",
              device.name.c_str(), o.width, o.height, o.frames, measured_frames(o, CloudAblation::Full), o.rounds, o.warmup);
  std::printf("%s\n", runs_markdown(runs).c_str());
  const std::vector<Summary> sums = summarize(runs, moving, o.views);
  std::printf("Targets (issue 23: full vs base at 30 Hz >= 5x / 3.5x / 3x ground / mixed / immersed in every round; "
              "the 60 Hz split >= 50 %% cheaper at >= 35 dB; light grid < 5 %%; >= 20 fps by the wall clock at 320x180 "
              "on lavapipe, full method, 60 Hz):\n\n%s\n",
              summary_markdown(sums).c_str());
  std::printf("CPU per frame: the simulation %.3f ms (60 Hz steps, timed apart after the matrix); extraction, graph and "
              "recording are the CPU ms above.\n\n",
              simulation_ms);
  if (growth) std::printf("%s\n", growth_markdown(*growth, o.width, o.height, o.modes.back()).c_str());
  std::printf("GPU memory (bytes):\n");
  for (auto& [k, v] : memory.items()) std::printf("  %-40s %12llu\n", k.c_str(), (unsigned long long)v.get<uint64_t>());
  if (o.out.empty()) return;
  nlohmann::ordered_json j = bench_json(o, device, memory, runs, sums);
  j["cpu"] = {{"simulation_ms_per_frame_60hz", simulation_ms}};
  if (growth) j["evolving"] = growth_json(*growth);
  write_file_atomic(o.out, j.dump(2) + "\n");
  std::printf("cumulo bench: wrote %s\n", o.out.c_str());
}

int run_bench(const BenchOptions& o, const CloudsRun& clouds) {
  render::CloudFeature& feature = clouds.feature;
  app::HeadlessSessionDesc d;
  d.sim.level = o.level;
  d.sim.modules = clouds.modules;
  d.width = o.width;
  d.height = o.height;
  app::HeadlessSession session(d);
  session.renderer().set_lod_error_px(o.lod_error_px);
  if (!feature.resources()) fail("%s: the level has no Cloudscape entity to measure", o.level.c_str());
  feature.set_measure_steps(true);
  // The matrix; moving: full runs with the light grid updating every frame. The sample level's sun is
  // still, so the light grid rests once built (light_grid_sweep.comp); these runs keep its updates going
  // (as a moving sun does) to measure what they cost.
  // The matrix; moving: full runs with the light grid updating every frame. The sample level's sun is
  // still, so the light grid rests once built (light_grid_sweep.comp); these runs keep its updates going
  // (as a moving sun does) to measure what they cost. A view's modes take turns within a round for each
  // ablation (kModeChunks): the split's saving compares them.
  std::vector<Run> runs, moving;
  struct Group {
    std::vector<Run>* list;
    std::vector<size_t> index;  // the group's runs in `list`, one per mode
    bool sun_moving;
  };
  std::vector<Group> groups;
  for (const std::string& view : o.views)
    for (CloudAblation ablation : o.ablations) {
      Group g{&runs, {}, false};
      for (int mode : o.modes) {
        g.index.push_back(runs.size());
        runs.push_back(Run{view, ablation, mode});
      }
      groups.push_back(g);
    }
  if (std::find(o.ablations.begin(), o.ablations.end(), CloudAblation::Full) != o.ablations.end())
    for (const std::string& view : o.views) {
      Group g{&moving, {}, true};
      for (int mode : o.modes) {
        g.index.push_back(moving.size());
        moving.push_back(Run{view, CloudAblation::Full, mode});
      }
      groups.push_back(g);
    }
  const size_t total = (runs.size() + moving.size()) * o.rounds;
  size_t done = 0;
  for (uint32_t round = 0; round < o.rounds; ++round)
    for (const Group& g : groups) {
      std::vector<RoundSamples> samples(g.index.size());
      for (uint32_t chunk = 0; chunk < kModeChunks; ++chunk)
        for (size_t k = 0; k < g.index.size(); ++k) {
          Run& run = (*g.list)[g.index[k]];
          const uint32_t frames = chunk_frames(measured_frames(o, run.ablation), chunk);
          if (frames == 0) continue;
          measure_chunk(session, feature, run, samples[k], g.sun_moving, chunk == 0 ? o.warmup : kChunkWarmup, frames);
        }
      for (size_t k = 0; k < g.index.size(); ++k) {
        Run& run = (*g.list)[g.index[k]];
        finish_round(run, samples[k]);
        if (round + 1 == o.rounds && !g.sun_moving) keep_image(session, o, run);
        const RoundFigures& last = run.rounds.back();
        std::fprintf(stderr, "cumulo bench: [%zu/%zu] %s %s%s %d Hz: clouds %.2f ms, GPU sum %.2f ms, wall %.2f ms (CPU %.2f), %.1f steps/px\n",
                     ++done, total, run.view.c_str(), render::ablation_name(run.ablation),
                     g.sun_moving ? " (light grid updating)" : "", run.mode, last.cloud_ms, last.frame_ms, last.wall_ms,
                     last.cpu_ms, median(run.steps));
      }
    }
  feature.options().light_grid_always_update = false;
  feature.set_measure_steps(false);
  finish_runs(runs, moving);
  const nlohmann::ordered_json memory = measure_memory(session, feature, o);
  const double simulation_ms = measure_simulation(session, 30);
  std::optional<GrowthFigures> growth;
  if (o.evolving != "off") {
    std::fprintf(stderr, "cumulo bench: the evolving view (%s)\n", o.evolving.c_str());
    growth = measure_growth(session, feature, o.evolving, o.modes.back(), std::max<uint32_t>(o.frames, 4));
  }
  const int code = session.finish();
  report(o, session.ctx().info(), memory, runs, moving, simulation_ms, growth ? &*growth : nullptr);
  return code;
}

}  // namespace

void register_bench_command(CommandRegistry& registry, const CloudsRun& clouds) {
  registry.add({"bench", "measure the cloud renderer: cameras x ablations x budget modes (table + JSON)", [clouds](int argc, char** argv) {
                  BenchOptions o;
                  std::string size, views, ablations, modes;
                  ArgParser p("cumulo bench",
                              "Measure the cloud renderer on this device: the level's cameras x the talk's ablation steps\n"
                              "(base, voxel-lighting, full) x budget modes (30: one march, 60: near/far split). Prints a\n"
                              "markdown table; --out writes JSON (device, size, frames, memory, runs).");
                  p.option("--level", "LEVEL", "level with a Cloudscape (default content/levels/sample/level.json)", &o.level)
                      .option("--size", "WxH", "render size (default 320x180; 960x540 on a GPU)", &size)
                      .option("--frames", "N", "measured frames per run (default 6; the full method 4 times as many)", &o.frames)
                      .option("--warmup", "N", "frames rendered before measuring (default 3)", &o.warmup)
                      .option("--rounds", "N", "times the whole matrix is run in turn, samples pooled (default 3)", &o.rounds)
                      .option("--out", "FILE.json", "write the results as JSON", &o.out)
                      .option("--images", "DIR", "write each run's converged image (what the split's PSNR compares) to DIR/VIEW_ABLATION_MODEhz.png",
                              &o.images)
                      .option("--views", "A,B", "cameras (default ground,mixed,immersed)", &views)
                      .option("--ablations", "A,B", "ablation steps (default base,voxel-lighting,full)", &ablations)
                      .option("--modes", "30,60", "budget modes (default 30,60)", &modes)
                      .option("--evolving", "CAMERA",
                              "the evolving view: the level's growing cloud (CloudGrowth) from CAMERA, stepped and "
                              "rebuilt while measured, in the last budget mode (default squall; off: not measured)",
                              &o.evolving)
                      .option("--lod-error", "PX", "the terrain's level of detail: a chunk's error within PX pixels (default 3; 0: full detail)",
                              &o.lod_error_px)
                      .range(0, 100);
                  clouds.add_run_options(p);  // --cloud-formats, --cloud-temporal, ...
                  if (!p.parse(argc, argv)) return 0;
                  if (!size.empty()) app::parse_size(size, o.width, o.height);
                  if (o.frames < 1 || o.frames > 1000) fail("--frames: %u is outside 1..1000", o.frames);
                  if (o.warmup > 100) fail("--warmup: %u is outside 0..100", o.warmup);
                  if (o.rounds < 1 || o.rounds > 100) fail("--rounds: %u is outside 1..100", o.rounds);
                  if (!o.images.empty()) {
                    std::error_code ec;
                    std::filesystem::create_directories(o.images, ec);
                    if (ec) fail("--images: cannot create the folder %s: %s", o.images.c_str(), ec.message().c_str());
                  }
                  if (!views.empty()) o.views = split_list(views);
                  if (o.views.empty()) fail("--views: no camera named");
                  if (!ablations.empty()) {
                    o.ablations.clear();
                    for (const std::string& a : split_list(ablations)) {
                      o.ablations.push_back(parse_name_or_fail(render::kCloudAblationNames, "--ablations", a));
                    }
                  }
                  if (!modes.empty()) {
                    o.modes.clear();
                    for (const std::string& m : split_list(modes))
                      o.modes.push_back(cumulo::render::budget_hz(cumulo::render::parse_budget_mode(m)));
                  }
                  return run_bench(o, clouds);
                }});
}

}  // namespace cumulo::clouds
