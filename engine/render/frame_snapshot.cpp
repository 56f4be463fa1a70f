#include "engine/render/frame_snapshot.h"

#include "engine/core/error.h"
#include "engine/render/sky_model.h"
#include "engine/scene/sun.h"

namespace cumulo::render {

FrameSnapshot extract_frame(const ecs::World& world, ecs::Entity camera, uint32_t width, uint32_t height) {
  FrameSnapshot s;
  s.width = width;
  s.height = height;
  const auto* ct = world.try_get<scene::Transform>(camera);
  const auto* cc = world.try_get<scene::Camera>(camera);
  const auto* name = world.try_get<ecs::Name>(camera);
  if (name) s.camera_name = name->value;
  if (!ct || !cc)
    fail("camera entity \"%s\" has no %s component", name ? name->value.c_str() : "(unnamed)", ct ? "Camera" : "Transform");
  s.camera = scene::make_camera_view(*ct, *cc, height ? float(width) / float(height) : 1.0f);

  scene::ConstSunSource sun = scene::find_sun(world);
  scene::TimeOfDay tod = sun.time ? *sun.time : scene::TimeOfDay{};
  s.sun = scene::sun_light(tod, sun.sun ? *sun.sun : scene::Sun{});
  s.time_of_day_hours = tod.hours;
  s.lighting = sky_lighting(s.sun, s.camera.position.y);

  world.view<const scene::ModelRef, const scene::Transform>().each([&](const scene::ModelRef& m, const scene::Transform& tr) {
    if (m.model) s.models.push_back({m.model, tr.matrix()});
  });
  world.view<const scene::Ocean>().each([&](const scene::Ocean& o) { if (!s.ocean) s.ocean = o; });
  return s;
}

}  // namespace cumulo::render
