#include "modules/clouds/weather/weather_systems.h"

#include <string>

#include "engine/app/sim_resources.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::clouds::weather {

void add_weather_scheduler_system(ecs::Scheduler& s) {
  s.add_system(ecs::Phase::Update, "weather scheduler", [](ecs::World& w, const ecs::FrameContext& f) {
    const ecs::World& cw = w;
    const scene::ConstSunSource sun = scene::find_sun(cw);
    const float hours = sun.time ? sun.time->hours : 12.0f;
    const auto* seed = w.try_resource<app::SimulationSeed>();
    // The viewer's zone (none without a viewer or outside every zone).
    ZoneCycle zone;
    if (const auto* viewer = w.try_resource<app::Viewer>())
      if (const auto* t = cw.try_get<scene::Transform>(viewer->entity))
        if (const WeatherZone* z = active_zone(w, t->position))
          zone = {z->name.empty() ? std::string("(unnamed zone)") : z->name, &z->states};
    w.view<WeatherScheduler>().each(
        [&](WeatherScheduler& ws) { advance(ws, float(f.dt), hours, seed ? seed->value : 1, zone); });
  });
}

}  // namespace cumulo::clouds::weather
