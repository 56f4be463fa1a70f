#include "engine/render/frame_snapshot.h"

#include "engine/core/error.h"
#include "engine/scene/sun.h"

namespace cumulo::render {

FrameSnapshot extract_frame(const ecs::World& world, ecs::Entity camera, uint32_t width, uint32_t height) {
  FrameSnapshot s;
  s.width = width;
  s.height = height;
  const auto* ct = world.try_get<scene::Transform>(camera);
  const auto* cc = world.try_get<scene::Camera>(camera);
  if (!ct || !cc) fail("camera entity has no %s", ct ? "Camera" : "Transform");
  if (const auto* n = world.try_get<ecs::Name>(camera)) s.camera_name = n->value;
  s.camera = scene::make_camera_view(*ct, *cc, height ? float(width) / float(height) : 1.0f);

  // Time of day: a world resource wins over a component (levels may use either).
  const scene::TimeOfDay* tod = world.try_resource<scene::TimeOfDay>();
  const scene::Sun* sun = world.try_resource<scene::Sun>();
  if (!tod) world.view<const scene::TimeOfDay>().each([&](const scene::TimeOfDay& t) { if (!tod) tod = &t; });
  if (!sun) world.view<const scene::Sun>().each([&](const scene::Sun& x) { if (!sun) sun = &x; });
  scene::TimeOfDay t = tod ? *tod : scene::TimeOfDay{};
  scene::SunPosition p = scene::sun_position(t);
  s.sun.direction = p.direction;
  s.sun.elevation_deg = p.elevation_deg;
  s.sun.time_of_day_hours = t.hours;
  s.sun.illuminance = sun ? sun->illuminance : 1.0f;
  s.sun.color = (sun ? sun->color : glm::vec3(1.0f)) * scene::sun_transmittance(p.elevation_deg);

  world.view<const scene::ModelRef, const scene::Transform>().each([&](const scene::ModelRef& m, const scene::Transform& tr) {
    if (m.model) s.models.push_back({m.model, tr.matrix()});
  });
  world.view<const scene::Ocean>().each([&](const scene::Ocean& o) { if (!s.ocean) s.ocean = o; });
  return s;
}

}  // namespace cumulo::render
