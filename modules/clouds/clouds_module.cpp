#include "modules/clouds/clouds_module.h"

#include "engine/core/error.h"
#include "engine/ecs/world.h"
#include "modules/clouds/bake/bake_command.h"
#include "modules/clouds/bake/grow/grow_command.h"
#include "modules/clouds/bench/bench_command.h"
#include "modules/clouds/soak/soak_command.h"
#include "modules/clouds/envelope/orographic_clouds.h"
#include "modules/clouds/frame/cloud_extraction.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/reference/reference_command.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/scene/cloudscape_assets.h"
#include "modules/clouds/volume/import_command.h"
#include "modules/clouds/weather/level_weather.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_systems.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::clouds {

void CloudsModule::register_commands(CommandRegistry& registry) {
  register_noise_command(registry);
  register_import_command(registry);
  register_bake_command(registry);
  register_grow_command(registry);
}

void CloudsModule::register_run_commands(CommandRegistry& registry, const app::Modules& all) {
  // The registry keeps the commands (and so this module and the list) for the process's life.
  const CloudsRun run{feature_, [this](ArgParser& p) { add_run_options(p); }, all};
  register_bench_command(registry, run);
  register_reference_command(registry, run);
  register_fidelity_command(registry, run);
  register_soak_command(registry, run);
}

void CloudsModule::register_components(ecs::ComponentRegistry& registry) {
  register_cloudscape_component(registry);
  envelope::register_orographic_clouds_component(registry);
  gameplay::register_stormbird_component(registry);
  gameplay::register_cloud_growth_component(registry);
  gameplay::register_lightning_component(registry);
  gameplay::register_trigger_component(registry);
  registry.register_component<weather::WeatherScheduler>(
      "WeatherScheduler", [](const weather::WeatherScheduler& s) { return weather::weather_scheduler_to_json(s); },
      [](const JsonView& v) { return weather::weather_scheduler_from_json(v); });
  registry.register_component<weather::WeatherZone>(
      "WeatherZone", [](const weather::WeatherZone& z) { return weather::weather_zone_to_json(z); },
      [](const JsonView& v) { return weather::weather_zone_from_json(v); });
}

void CloudsModule::add_run_options(ArgParser& p) { add_cloud_run_options(p, feature_.options(), simulation_); }

std::filesystem::path CloudsModule::weather_folder() const {
  if (!simulation_.weather_dir.empty()) return simulation_.weather_dir;
  return level_weather_folder_.empty() ? weather::WeatherLibrary::default_folder() : level_weather_folder_;
}

void CloudsModule::on_level_loaded(ecs::World& world, const scene::LevelInfo& level) {
  const auto folder = level.folders.find("weather");
  level_weather_folder_ = folder == level.folders.end() ? std::filesystem::path() : folder->second;
  std::error_code ec;
  if (!level_weather_folder_.empty() && simulation_.weather_dir.empty() && !std::filesystem::is_directory(level_weather_folder_, ec))
    fail("%s: $.folders.weather: %s is not a folder (of weather states)", level.file.string().c_str(),
         level_weather_folder_.string().c_str());
  world.view<Cloudscape>().each([&](ecs::Entity e, Cloudscape& c) {
    if (c.asset.empty() && !world.try_get<gameplay::CloudGrowth>(e))
      fail("%s: expected \"asset\": a recipe (.json) or a folder of .nvdf files (only a cloud grown during play, an "
           "entity with a CloudGrowth, has none)",
           c.where.c_str());
  });
  const bool any = resolve_cloudscapes(world, level.directory);
  weather::load_level_weather(world, level.file, weather_folder(), simulation_.weather,
                              gameplay::trigger_weather_references(world, level.file));
  bool scheduler = false;
  static_cast<const ecs::World&>(world).view<const weather::WeatherScheduler>().each(
      [&](const weather::WeatherScheduler&) { scheduler = true; });
  bool orographic = false;
  std::string first_orographic;
  world.view<envelope::OrographicClouds>().each([&](ecs::Entity, envelope::OrographicClouds& c) {
    // One set of envelope maps per level (the renderer bakes one): a second would be dropped without a word.
    if (orographic)
      fail("%s: a level holds one OrographicClouds component (%s has one already): put the second's rules in it",
           c.where.c_str(), first_orographic.c_str());
    envelope::resolve_orographic_clouds(c, level.directory);
    orographic = true;
    first_orographic = c.where;
  });
  world.view<gameplay::CloudGrowth>().each([&](ecs::Entity e, gameplay::CloudGrowth& g) {
    if (!world.try_get<Cloudscape>(e))
      fail("%s: a CloudGrowth grows the cloud of its entity's Cloudscape, and this entity has none", g.where.c_str());
    gameplay::resolve_cloud_growth(g, level.directory);
  });
  feature_.on_level_loaded(any, scheduler, orographic);
}

void CloudsModule::extract(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) {
  extract_cloud_frame(world, snapshot);
}

void CloudsModule::register_systems(ecs::Scheduler& s) {
  gameplay::add_trigger_system(s);
  gameplay::add_stormbird_system(s);
  weather::add_weather_scheduler_system(s);
  gameplay::add_cloud_growth_system(s);  // after the schedulers: their states start it
  gameplay::add_lightning_system(s);  // after the schedulers: their weather sets the lightning's
}

std::shared_ptr<CloudsModule> make_clouds_module() { return std::make_shared<CloudsModule>(); }

}  // namespace cumulo::clouds
