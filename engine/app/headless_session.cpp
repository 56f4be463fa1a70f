#include "engine/app/headless_session.h"

#include "engine/app/frame_output.h"
#include "engine/app/module.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/render/frame_renderer.h"

namespace cumulo::app {

struct HeadlessSession::Gpu {
  render::FrameRenderer renderer;
  OffscreenOutput output;
  gpu::FrameRing ring;
  Gpu(gpu::Context& ctx, uint32_t w, uint32_t h) : renderer(ctx), output(ctx, w, h), ring(ctx, 1) {}
};

HeadlessSession::HeadlessSession(const HeadlessSessionDesc& desc)
    : modules_(desc.sim.modules), owned_sim_(std::make_unique<Simulation>(desc.sim)), sim_(owned_sim_.get()),
      width_(desc.width), height_(desc.height) {
  create_gpu(desc.aerial_lut);
}

HeadlessSession::HeadlessSession(Simulation& sim, const Modules& modules, uint32_t width, uint32_t height, bool aerial_lut)
    : modules_(modules), sim_(&sim), width_(width), height_(height) {
  create_gpu(aerial_lut);
}

void HeadlessSession::create_gpu(bool aerial_lut) {
  ctx_ = std::make_unique<gpu::Context>(gpu::ContextDesc{});
  LOG_INFO("device: %s (%s)", ctx_->info().name.c_str(), ctx_->info().driver_info.c_str());
  gpu_ = std::make_unique<Gpu>(*ctx_, width_, height_);
  gpu_->renderer.set_aerial_perspective_lut(aerial_lut);
  for (const auto& m : modules_) gpu_->renderer.add_feature(*m);
}

HeadlessSession::~HeadlessSession() {
  if (ctx_) ctx_->wait_idle();
  gpu_.reset();  // the renderer's destructor calls every module's destroy_gpu
}

render::FrameRenderer& HeadlessSession::renderer() { return gpu_->renderer; }

render::FrameSnapshot HeadlessSession::extract(ecs::Entity camera, render::BudgetMode mode) {
  sim_->extract();
  render::FrameSnapshot s = render::extract_frame(sim_->world(), camera, width_, height_);
  s.mode = mode;
  s.frame_index = frame_index_ + 1;
  s.sim_time = sim_->sim_seconds();  // steps / rate: exact, unlike a running sum of dt
  s.sim_step = sim_->steps();
  for (const auto& m : modules_) m->extract(sim_->world(), s);
  return s;
}

void HeadlessSession::submit(render::FrameSnapshot& snapshot) {
  snapshot.frame_index = ++frame_index_;
  gpu::Frame& fr = gpu_->ring.begin();
  gpu_->renderer.record_frame(fr.cmd, snapshot, gpu_->output.target(), fr.slot);
  gpu_->ring.submit(fr);
}

void HeadlessSession::wait_frame() {
  gpu_->ring.wait_all();
  gpu_->output.after_frame();
}

void HeadlessSession::render(render::FrameSnapshot& snapshot) {
  submit(snapshot);
  wait_frame();
}

void HeadlessSession::render(ecs::Entity camera, render::BudgetMode mode) {
  render::FrameSnapshot s = extract(camera, mode);
  render(s);
}

std::vector<std::pair<std::string, double>> HeadlessSession::pass_timings() const { return gpu_->renderer.pass_timings(); }

gpu::Rgba8Image HeadlessSession::screenshot() { return gpu::read_image_rgba8(*ctx_, gpu_->output.image()); }

int HeadlessSession::finish() {
  ctx_->wait_idle();
  if (ctx_->validation_errors() == 0) return 0;
  LOG_ERROR("%u Vulkan validation errors (last: %s)", ctx_->validation_errors(), ctx_->last_validation_message().c_str());
  return 3;
}

}  // namespace cumulo::app
