#include "modules/clouds/bench/bench_growth.h"

#include <algorithm>
#include <cstdio>
#include <functional>

#include "engine/app/headless_session.h"
#include "engine/core/error.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/gpu/timestamps.h"
#include "modules/clouds/bench/bench_runs.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/grow_gpu/gpu_solver.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/scene/cloudscape.h"

namespace cumulo::clouds::bench {
namespace {

// Steps taken before measuring: a cloud well under way (the simulation's and the flood's cost hardly depend on the
// cloud; the march's and the light grid's do), caught up at up to this many steps a frame.
constexpr int kWarmSteps = 40;
constexpr int kCatchUpPerFrame = 64;
// The apart timings (a step, the distance field, the attributes), each the median of this many.
constexpr int kApartRepeats = 3;

struct Frame {
  double wall_ms = 0;
  bool stepped = false, update_work = false, updated = false;  // updated: the images changed (the update's last run)
  double grow_ms = 0, asset_ms = 0, light_grid_ms = 0;
};

Frame render_frame(app::HeadlessSession& session, render::CloudGrowthRuntime* runtime, ecs::Entity camera, int mode,
                   const std::function<render::CloudGrowthRuntime*()>& find) {
  const int steps_before = runtime ? runtime->steps_done() : 0;
  const int updates_before = runtime ? runtime->grown().updates_recorded() : 0;
  const int stages_before = runtime ? runtime->grown().stages_recorded() : 0;
  const Stopwatch clock;
  cumulo::render::FrameSnapshot snapshot = session.extract(camera, cumulo::render::BudgetMode(mode));
  session.submit(snapshot);
  session.wait_frame();
  Frame f;
  f.wall_ms = clock.ms();
  if (!runtime) runtime = find();
  if (runtime) {
    f.stepped = runtime->steps_done() > steps_before;
    f.updated = runtime->grown().updates_recorded() > updates_before;
    f.update_work = runtime->grown().stages_recorded() > stages_before;
  }
  for (const auto& [name, ms] : session.pass_timings()) {
    if (name == render::kGrowPass) f.grow_ms += ms;
    if (name == render::kGrowAssetPass) f.asset_ms += ms;
    if (name.rfind("clouds.light_grid", 0) == 0) f.light_grid_ms += ms;
  }
  return f;
}

}  // namespace

double GrowthFigures::fps_growing() const {
  if (held_ms <= 0) return 0;
  // A second of play at the rate: steps_per_second frames that step, update_frames as many that update, the rest
  // held.
  // Without the spread the frame that steps updates too.
  const double updates = update_frames_setting > 0 ? std::max(1.0, update_frames) * std::max(0.0, updating_ms - held_ms) : 0.0;
  const double extra = steps_per_second * (std::max(0.0, stepping_ms - held_ms) + updates);
  return std::max(0.0, 1000.0 - extra) / held_ms;
}

GrowthFigures measure_growth(app::HeadlessSession& session, render::CloudFeature& feature, const std::string& camera_name,
                             int mode, int frames) {
  GrowthFigures g;
  g.camera = camera_name;
  ecs::World& world = session.sim().world();
  ecs::Entity entity = ecs::Entity::null();
  world.view<gameplay::CloudGrowth>().each([&](ecs::Entity e, gameplay::CloudGrowth& c) {
    if (entity.is_null() && world.try_get<Cloudscape>(e) && !c.resolved_spec.empty()) entity = e;
  });
  if (entity.is_null()) {
    g.why_not = "the level has no cloud that grows during play (CloudGrowth)";
    return g;
  }
  ecs::Entity camera = ecs::Entity::null();
  try {
    camera = session.sim().camera(camera_name);
  } catch (const Error& e) {
    g.why_not = e.what();
    return g;
  }
  gameplay::CloudGrowth& c = world.get<gameplay::CloudGrowth>(entity);
  const gameplay::CloudGrowth saved = c;
  g.spec = c.resolved_spec.string();
  g.steps_per_second = gameplay::growth_steps_per_second(c);
  g.last_step = c.last_step;
  g.build_seconds = g.steps_per_second > 0 ? double(c.last_step) / g.steps_per_second : 0;
  render::CloudRenderOptions& options = feature.options();
  const render::CloudRenderOptions saved_options = options;
  const uint64_t key = entity.bits();
  auto find = [&] { return feature.growth_runtime(key); };

  // Caught up to a cloud under way, then two frames for its images and light grid.
  c.running = true;
  c.paused = false;
  c.target_steps = std::min(kWarmSteps, std::max(c.last_step, 1));
  options.growth_steps_per_frame = kCatchUpPerFrame;
  options.growth_spread = false;
  render::CloudGrowthRuntime* runtime = nullptr;
  for (int f = 0; f < 8 && (!runtime || runtime->steps_done() < c.target_steps); ++f) {
    render_frame(session, runtime, camera, mode, find);
    runtime = find();
  }
  if (!runtime) {
    c = saved;
    options = saved_options;
    g.why_not = "the growing cloud has no runtime (not drawn: over the GPU budget?)";
    return g;
  }
  for (int f = 0; f < 3; ++f) render_frame(session, runtime, camera, mode, find);

  const grow_gpu::GrownAssetGrid& grid = runtime->grown().grid();
  for (int a = 0; a < 3; ++a) {
    g.cells[a] = grid.cells[a];
    g.voxels[a] = grid.voxels[a];
  }
  g.voxel_m = grid.voxel;

  // Held: the same frame again (the light grid rests).
  std::vector<double> held;
  for (int f = 0; f < frames; ++f) held.push_back(render_frame(session, runtime, camera, mode, find).wall_ms);

  // Growing at the renderer's pace: one more step wanted every frame, so a frame that steps is followed by the
  // frames of its update (the level's options: spread, update frames). At least two whole updates are measured.
  options.growth_steps_per_frame = 1;
  options.growth_spread = saved_options.growth_spread;
  options.growth_update_frames = saved_options.growth_update_frames;
  g.update_frames_setting =
      options.growth_spread ? render::growth_update_frames_for_device(options, session.ctx().info().is_cpu()) : 0;
  std::vector<double> growing, stepping, updating, grow_ms, light_ms, updated_frames;
  double asset_total = 0.0;
  int updates = 0, update_work_frames = 0;
  for (int f = 0; (f < 2 * frames || updates < 2) && f < 8 * frames + 32 && runtime->steps_done() < c.last_step; ++f) {
    c.target_steps = std::min(c.last_step, runtime->steps_done() + 1);
    const Frame fr = render_frame(session, runtime, camera, mode, find);
    growing.push_back(fr.wall_ms);
    g.worst_ms = std::max(g.worst_ms, fr.wall_ms);
    if (fr.stepped) {
      stepping.push_back(fr.wall_ms);
      grow_ms.push_back(fr.grow_ms);
    }
    if (fr.update_work && (!fr.stepped || !options.growth_spread)) {
      updating.push_back(fr.wall_ms);
      ++update_work_frames;
    }
    if (fr.update_work) asset_total += fr.asset_ms;
    if (fr.updated) {
      ++updates;
      updated_frames.push_back(fr.wall_ms);
      light_ms.push_back(fr.light_grid_ms);
    }
  }

  // An update spread over frames that is still under way is finished first (its runs share the scratch buffers the
  // apart timings use).
  c.target_steps = runtime->steps_done();
  for (int f = 0; f < 40 && runtime->updating(); ++f) render_frame(session, runtime, camera, mode, find);

  // Apart, outside the frame: a step, the distance field, the attributes.
  gpu::Context& ctx = session.ctx();
  ctx.wait_idle();
  std::vector<double> step_ms, sdf_ms, attributes_ms, images_ms;
  gpu::GpuTimer timer(ctx, 1, 16);
  for (int k = 0; k < kApartRepeats && runtime->steps_done() < c.last_step; ++k) {
    timer.begin_frame(0);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
      const uint32_t r = timer.begin(cmd, "step");
      runtime->record_steps(cmd, 1);
      timer.end(cmd, r);
      runtime->record_update(cmd, {0, INT32_MAX}, &timer, grow_gpu::GrownUpdateOrder::Apart);
    });
    for (const gpu::TimedRange& t : timer.collect(0)) {
      if (t.name == "step") step_ms.push_back(t.ms);
      if (t.name == "grown.sdf") sdf_ms.push_back(t.ms);
      if (t.name == "grown.attributes") attributes_ms.push_back(t.ms);
      if (t.name == "grown.images") images_ms.push_back(t.ms);
    }
  }
  c = saved;
  c.target_steps = std::max(saved.target_steps, 0);
  options = saved_options;

  g.step_ms = median(step_ms);
  g.sdf_ms = median(sdf_ms);
  g.attributes_ms = median(attributes_ms);
  g.images_ms = median(images_ms);
  g.update_ms = updates > 0 ? asset_total / updates : 0.0;  // a whole update, over its frames
  g.update_frames = updates > 0 ? double(update_work_frames) / updates : 0.0;
  g.light_grid_ms = median(light_ms);
  g.held_ms = median(held);
  g.growing_ms = median(growing);
  g.stepping_ms = median(stepping);
  g.updating_ms = median(updating);
  g.images_frame_ms = median(updated_frames);
  const double grow_frame_ms = median(grow_ms);
  if (g.step_ms <= 0) g.step_ms = grow_frame_ms;
  g.amortized_ms = g.held_ms > 0 ? g.steps_per_second * (g.step_ms + g.update_ms + g.light_grid_ms) / g.fps_held() : 0;
  g.measured = !held.empty() && !stepping.empty() && !updating.empty();
  if (!g.measured) g.why_not = "the cloud reached its last step before it could be measured growing";
  return g;
}

std::string growth_markdown(const GrowthFigures& g, unsigned width, unsigned height, int mode) {
  if (!g.measured) return strf("Evolving view: not measured (%s).\n", g.why_not.c_str());
  std::string s = strf(
      "Evolving view (issue 26): `%s` from the camera `%s`, %ux%u, %d Hz; %dx%dx%d cells -> %dx%dx%d voxels of %.0f m; "
      "%.2f steps per second of play, %d steps: built in %.0f s of play.\n\n",
      g.spec.c_str(), g.camera.c_str(), width, height, mode, g.cells[0], g.cells[1], g.cells[2], g.voxels[0], g.voxels[1],
      g.voxels[2], g.voxel_m, g.steps_per_second, g.last_step, g.build_seconds);
  s += "| GPU ms: simulation step | distance field (SDF) | attributes | images | update in the frames (all) | light grid "
       "in the update's last frame (a rebuild, or the sweep's first level) |\n";
  s += "|---|---|---|---|---|---|\n";
  s += strf("| %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n\n", g.step_ms, g.sdf_ms, g.attributes_ms, g.images_ms,
            g.update_ms, g.light_grid_ms);
  s += strf("The update over %s (measured: %.1f frames an update).\n\n",
            g.update_frames_setting > 0 ? strf("%d frames", g.update_frames_setting).c_str() : "the frame that steps",
            g.update_frames);
  s += "| frame ms (wall): held | growing (median) | a frame that steps | a frame of the update (median) | the update's last "
       "(images, light grid) | worst frame growing | fps held | fps growing at its rate | growth per frame at its rate "
       "(GPU ms) |\n";
  s += "|---|---|---|---|---|---|---|---|---|\n";
  s += strf("| %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %.1f | %.2f |\n", g.held_ms, g.growing_ms, g.stepping_ms,
            g.updating_ms, g.images_frame_ms, g.worst_ms, g.fps_held(), g.fps_growing(), g.amortized_ms);
  return s;
}

nlohmann::ordered_json growth_json(const GrowthFigures& g) {
  nlohmann::ordered_json j;
  j["measured"] = g.measured;
  if (!g.measured) {
    j["why_not"] = g.why_not;
    return j;
  }
  j["camera"] = g.camera;
  j["spec"] = g.spec;
  j["cells"] = {g.cells[0], g.cells[1], g.cells[2]};
  j["voxels"] = {g.voxels[0], g.voxels[1], g.voxels[2]};
  j["voxel_m"] = g.voxel_m;
  j["steps_per_second_of_play"] = g.steps_per_second;
  j["last_step"] = g.last_step;
  j["build_seconds_of_play"] = g.build_seconds;
  j["gpu_ms"] = {{"simulation_step", g.step_ms},
                 {"sdf", g.sdf_ms},
                 {"attributes", g.attributes_ms},
                 {"images", g.images_ms},
                 {"update_in_frames", g.update_ms},
                 {"light_grid", g.light_grid_ms}};
  j["update_frames"] = g.update_frames_setting;  // 0: the update in the frame that steps (no spread)
  j["update_frames_measured"] = g.update_frames;
  j["frame_ms"] = {{"held", g.held_ms},       {"growing", g.growing_ms},          {"stepping", g.stepping_ms},
                   {"updating", g.updating_ms}, {"images", g.images_frame_ms}, {"worst_growing", g.worst_ms}};
  j["fps_held"] = g.fps_held();
  j["fps_growing_at_rate"] = g.fps_growing();
  j["growth_gpu_ms_per_frame_at_rate"] = g.amortized_ms;
  return j;
}

}  // namespace cumulo::clouds::bench
