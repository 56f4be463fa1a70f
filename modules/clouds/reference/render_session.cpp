#include "modules/clouds/reference/render_session.h"

#include "engine/app/frame_output.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/render/frame_renderer.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/clouds_module.h"

namespace cumulo::clouds {

struct RenderSession::Gpu {
  cumulo::render::FrameRenderer renderer;
  app::OffscreenOutput output;
  gpu::FrameRing ring;
  Gpu(gpu::Context& ctx, uint32_t w, uint32_t h) : renderer(ctx), output(ctx, w, h), ring(ctx, 1) {}
};

RenderSession::RenderSession(const RenderSessionDesc& desc, CloudsModule& module) : desc_(desc), module_(module) {
  app::SimulationDesc sd;
  sd.level = desc.level;
  sd.time_of_day = desc.time_of_day;
  sd.modules = app::Modules{std::shared_ptr<app::Module>(&module, [](app::Module*) {})};
  sim_ = std::make_unique<app::Simulation>(sd);
  ctx_ = std::make_unique<gpu::Context>(gpu::ContextDesc{});
  LOG_INFO("device: %s (%s)", ctx_->info().name.c_str(), ctx_->info().driver_info.c_str());
  gpu_ = std::make_unique<Gpu>(*ctx_, desc.width, desc.height);
  gpu_->renderer.add_feature(module);
  if (!module.feature().resources()) fail("%s: the level has no Cloudscape entity", desc.level.c_str());
}

RenderSession::~RenderSession() {
  if (ctx_) ctx_->wait_idle();
  gpu_.reset();  // the renderer's destructor calls the module's destroy_gpu
}

ecs::Entity RenderSession::camera(const std::string& name) { return sim_->camera(name); }

void RenderSession::place_camera(ecs::Entity camera, glm::vec3 position, glm::vec3 target, float fov_y_deg) {
  ecs::World& w = sim_->world();
  if (auto* t = w.try_get<scene::Transform>(camera)) *t = scene::Transform::look_at(position, target);
  if (auto* c = w.try_get<scene::Camera>(camera)) c->fov_y_deg = fov_y_deg;
}

void RenderSession::set_time_of_day(float hours) { scene::time_of_day_to_set(sim_->world()).hours = hours; }
float RenderSession::time_of_day() const {
  const scene::ConstSunSource s = scene::find_sun(static_cast<const ecs::World&>(sim_->world()));
  return s.time ? s.time->hours : 12.0f;
}

void RenderSession::render(ecs::Entity camera) {
  sim_->extract();
  cumulo::render::FrameSnapshot s = cumulo::render::extract_frame(sim_->world(), camera, desc_.width, desc_.height);
  module_.extract(sim_->world(), s);
  s.mode = desc_.mode;
  s.frame_index = ++frame_index_;
  gpu::Frame& fr = gpu_->ring.begin();
  gpu_->renderer.record_frame(fr.cmd, s, gpu_->output.target(), fr.slot);
  gpu_->ring.submit(fr);
  gpu_->ring.wait_all();
  gpu_->output.after_frame();
}

gpu::Rgba8Image RenderSession::screenshot() { return gpu::read_image_rgba8(*ctx_, gpu_->output.image()); }

}  // namespace cumulo::clouds
