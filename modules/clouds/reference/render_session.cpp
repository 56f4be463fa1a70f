#include "modules/clouds/reference/render_session.h"

#include "engine/core/error.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"

namespace cumulo::clouds {

RenderSession::RenderSession(const RenderSessionDesc& desc, const CloudsRun& run) : desc_(desc) {
  app::HeadlessSessionDesc d;
  d.sim.level = desc.level;
  d.sim.time_of_day = desc.time_of_day;
  d.sim.modules = run.modules;
  d.width = desc.width;
  d.height = desc.height;
  session_ = std::make_unique<app::HeadlessSession>(d);
  if (!run.feature.resources()) fail("%s: the level has no Cloudscape entity", desc.level.c_str());
}

ecs::Entity RenderSession::camera(const std::string& name) { return sim().camera(name); }

void RenderSession::place_camera(ecs::Entity camera, glm::vec3 position, glm::vec3 target, float fov_y_deg) {
  ecs::World& w = sim().world();
  if (auto* t = w.try_get<scene::Transform>(camera)) *t = scene::Transform::look_at(position, target);
  if (auto* c = w.try_get<scene::Camera>(camera)) c->fov_y_deg = fov_y_deg;
}

void RenderSession::set_time_of_day(float hours) { scene::time_of_day_to_set(sim().world()).hours = hours; }
float RenderSession::time_of_day() const {
  const scene::ConstSunSource s = scene::find_sun(static_cast<const ecs::World&>(session_->sim().world()));
  return s.time ? s.time->hours : 12.0f;
}

void RenderSession::render(ecs::Entity camera) { session_->render(camera, desc_.mode); }

gpu::Rgba8Image RenderSession::screenshot() { return session_->screenshot(); }

}  // namespace cumulo::clouds
