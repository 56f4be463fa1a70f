#pragma once
// The cloud module's one registration point (DESIGN.md "Modules"): its subcommands (noise, bake,
// import, grow, bench, reference, fidelity), its components (Cloudscape, WeatherScheduler, WeatherZone,
// StormbirdDissipation, LightningEvent, Trigger) and their systems, its `cumulo run` flags
// (options/cloud_options.h), the level's weather (weather/level_weather.h), the frame's extraction
// (frame/cloud_extraction.h) and its render passes (render/cloud_feature.h). Each owner does its part;
// this file only wires them.
#include <filesystem>
#include <memory>

#include "engine/app/module.h"
#include "modules/clouds/options/cloud_options.h"
#include "modules/clouds/render/cloud_feature.h"

namespace cumulo::clouds {

class CloudsModule final : public app::Module {
 public:
  const char* name() const override { return "clouds"; }
  void register_commands(CommandRegistry& registry) override;
  // bench, reference, fidelity: they run the level with every module, measuring this one's renderer.
  void register_run_commands(CommandRegistry& registry, const app::Modules& all) override;
  void add_run_options(ArgParser& p) override;
  void register_components(ecs::ComponentRegistry& registry) override;
  void register_systems(ecs::Scheduler& s) override;
  void on_level_loaded(ecs::World& world, const scene::LevelInfo& level) override;
  void extract(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) override;
  void create_gpu(cumulo::render::GpuServices& g) override { feature_.create_gpu(g); }
  void destroy_gpu() override { feature_.destroy_gpu(); }
  void add_passes(cumulo::render::Stage stage, cumulo::render::StageContext& f) override { feature_.add_passes(stage, f); }

  render::CloudFeature& feature() { return feature_; }
  CloudSimulationOptions& simulation_options() { return simulation_; }
  // The folder of weather states: --weather-dir, else the loaded level's "folders": {"weather": ...}, else
  // the repository's content/weather/ (the editor saves there).
  std::filesystem::path weather_folder() const;

 private:
  render::CloudFeature feature_;
  CloudSimulationOptions simulation_;
  std::filesystem::path level_weather_folder_;  // the loaded level's (empty: it names none)
};

std::shared_ptr<CloudsModule> make_clouds_module();

}  // namespace cumulo::clouds
