#include "engine/app/detail/run_context.h"

#include <cstdio>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/gpu/allocator.h"
#include "engine/gpu/context.h"
#include "engine/render/frame_renderer.h"
#include "engine/render/graph/render_graph.h"
#include "engine/scene/components.h"

namespace cumulo::app::detail {

render::FrameSnapshot extract(RunContext& rc, uint32_t w, uint32_t h, uint64_t frame) {
  rc.sim.extract();
  render::FrameSnapshot s = render::extract_frame(rc.sim.world(), rc.camera, w, h);
  s.mode = rc.opt.mode;
  s.frame_index = frame;
  s.sim_time = rc.clock.sim_seconds();  // ticks / rate: exact, unlike a running sum of dt
  s.sim_step = rc.sim.steps();
  for (const auto& m : rc.modules) m->extract(rc.sim.world(), s);
  return s;
}

void add_module_features(RunContext& rc, render::FrameRenderer& renderer) {
  for (const auto& m : rc.modules) renderer.add_feature(*m);
}

void configure_resolution(RunContext& rc, const gpu::Context& ctx, bool windowed) {
  rc.resolution.set_budget_scale(rc.opt.budget_scale.value_or(render::default_budget_scale(ctx.info().is_cpu())));
  rc.resolution.set_enabled(!rc.opt.resolution_scale && rc.opt.dynamic_resolution.value_or(windowed));
}

float next_resolution_scale(const RunContext& rc) {
  return rc.opt.resolution_scale ? *rc.opt.resolution_scale : rc.resolution.scale();
}

void feed_resolution(RunContext& rc, const std::vector<std::pair<std::string, double>>& timings, double fallback_ms) {
  double gpu_ms = 0.0;
  for (const auto& t : timings) gpu_ms += t.second;
  rc.resolution.update(timings.empty() ? fallback_ms : gpu_ms, rc.opt.mode);
}

void write_stats(RunContext& rc, gpu::Context& ctx, uint32_t w, uint32_t h) {
  if (rc.opt.stats.empty()) return;
  RunStats::Info info;
  info.width = w;
  info.height = h;
  info.mode_hz = render::budget_hz(rc.opt.mode);
  info.sim_hz = rc.opt.sim_hz;
  info.seed = rc.opt.seed;
  info.sim_seconds = rc.clock.sim_seconds();
  info.level = rc.opt.level;
  if (const auto* n = rc.sim.world().try_get<ecs::Name>(rc.camera)) info.camera = n->value;
  const gpu::DeviceInfo& d = ctx.info();
  info.device_name = d.name;
  info.driver_name = d.driver_name;
  info.driver_info = d.driver_info;
  info.api_version = strf("%u.%u.%u", VK_API_VERSION_MAJOR(d.api_version), VK_API_VERSION_MINOR(d.api_version),
                          VK_API_VERSION_PATCH(d.api_version));
  info.validation_enabled = ctx.validation_enabled();
  info.validation_errors = ctx.validation_errors();
  info.validation_warnings = ctx.validation_warnings();
  info.peak_gpu_memory_bytes = ctx.allocator().stats().peak_allocated_bytes;
  info.dynamic_resolution = rc.resolution.enabled();
  info.frame_budget_ms = rc.resolution.budget_ms(rc.opt.mode);
  info.budget_scale = rc.resolution.budget_scale();
  info.resolution_changes = rc.resolution.changes();
  write_file_atomic(rc.opt.stats, rc.stats.to_json(info));
  std::printf("cumulo: wrote stats %s\n", rc.opt.stats.c_str());
}

void write_graph_dump(const std::string& path, const render::CompiledGraph& g) {
  bool dot = path.size() >= 4 && path.substr(path.size() - 4) == ".dot";
  write_file_atomic(path, dot ? g.to_dot() : g.to_text());
  std::printf("cumulo: wrote render graph %s\n", path.c_str());
}

void apply_fly_camera(ecs::World& world, ecs::Entity camera, const FlyCamera& fly) {
  auto& t = world.get<scene::Transform>(camera);
  t.position = fly.position;
  t.rotation = fly_rotation(fly);
}

FlyCamera fly_camera_from(const ecs::World& world, ecs::Entity camera) {
  const auto& t = world.get<scene::Transform>(camera);
  FlyCamera fly;
  fly.position = t.position;
  fly_look_along(fly, t.forward());
  return fly;
}

}  // namespace cumulo::app::detail
