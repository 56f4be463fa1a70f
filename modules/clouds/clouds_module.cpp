#include "modules/clouds/clouds_module.h"

#include "modules/clouds/bake/bake_command.h"
#include "modules/clouds/bake/grow/grow_command.h"
#include "modules/clouds/bench_command.h"
#include "modules/clouds/reference/reference_command.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/volume/import_command.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"
#include "engine/scene/components.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "engine/core/args.h"
#include "engine/app/simulation.h"
#include "engine/scene/sun.h"

namespace cumulo::clouds {

void CloudsModule::register_commands(CommandRegistry& registry) {
  register_noise_command(registry);
  register_import_command(registry);
  register_bake_command(registry);
  register_grow_command(registry);
  register_bench_command(registry);
  register_reference_command(registry);
  register_fidelity_command(registry);
}

void CloudsModule::register_components(ecs::ComponentRegistry& registry) {
  register_cloudscape_component(registry);
  gameplay::register_stormbird_component(registry);
  gameplay::register_lightning_component(registry);
  gameplay::register_trigger_component(registry);
  registry.register_component<weather::WeatherScheduler>(
      "WeatherScheduler", [](const weather::WeatherScheduler& s) { return weather::weather_scheduler_to_json(s); },
      [](const JsonView& v) { return weather::weather_scheduler_from_json(v); });
  registry.register_component<weather::WeatherZone>(
      "WeatherZone", [](const weather::WeatherZone& z) { return weather::weather_zone_to_json(z); },
      [](const JsonView& v) { return weather::weather_zone_from_json(v); });
}

void CloudsModule::add_run_options(ArgParser& p) { feature_.add_run_options(p); }

void CloudsModule::on_level_loaded(ecs::World& world, const scene::LevelInfo& level) {
  feature_.on_level_loaded(world, level);
}

void CloudsModule::register_systems(ecs::Scheduler& s) {
  gameplay::add_trigger_system(s);
  gameplay::add_stormbird_system(s);
  // The weather scheduler: the hour from the time of day that counts (scene::find_sun), the stream
  // from the run's seed.
  s.add_system(ecs::Phase::Update, "weather scheduler", [this](ecs::World& w, const ecs::FrameContext& f) {
    const weather::WeatherLibrary* library = feature_.weather_library();
    const scene::ConstSunSource sun = scene::find_sun(static_cast<const ecs::World&>(w));
    const float hours = sun.time ? sun.time->hours : 12.0f;
    const auto* seed = w.try_resource<app::SimulationSeed>();
    // The viewer's zone (none without a viewer or outside every zone).
    weather::ZoneCycle zone;
    if (const auto* viewer = w.try_resource<app::Viewer>())
      if (const auto* t = static_cast<const ecs::World&>(w).try_get<scene::Transform>(viewer->entity))
        if (const weather::WeatherZone* z = weather::active_zone(w, t->position))
          zone = {z->name.empty() ? std::string("(unnamed zone)") : z->name, &z->states};
    bool first = true;
    w.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& ws) {
      weather::advance(ws, float(f.dt), hours, seed ? seed->value : 1, zone);
      // The first scheduler's weather sets how often and where lightning strikes.
      if (!first || !library) return;
      first = false;
      auto* lw = w.try_resource<gameplay::LightningWeather>();
      if (!lw) lw = &w.set_resource<gameplay::LightningWeather>();
      const bool encounter_box = ws.encounter_active && ws.has_encounter_lightning_volume;
      lw->per_minute = ws.has_lightning_volume || encounter_box
                           ? weather::weather_now(ws, *library).state.lightning_per_minute : 0.0f;
      lw->box_min = encounter_box ? ws.encounter_lightning_min : ws.lightning_min;
      lw->box_max = encounter_box ? ws.encounter_lightning_max : ws.lightning_max;
    });
  });
  gameplay::add_lightning_system(s);
}

std::shared_ptr<app::Module> make_clouds_module() { return std::make_shared<CloudsModule>(); }

}  // namespace cumulo::clouds
