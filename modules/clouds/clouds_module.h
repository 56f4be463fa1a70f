#pragma once
// The cloud module's one registration point (DESIGN.md "Modules"): its subcommands (noise, bake,
// import, bench), its components (Cloudscape, WeatherScheduler, StormbirdDissipation) and systems, its
// `cumulo run` flags (the cloud flags; --event is the engine's) and its render passes.
#include <memory>

#include "engine/app/module.h"
#include "modules/clouds/render/cloud_feature.h"

namespace cumulo::clouds {

class CloudsModule final : public app::Module {
 public:
  const char* name() const override { return "clouds"; }
  void register_commands(CommandRegistry& registry) override;
  void add_run_options(ArgParser& p) override;
  void check_run_options() override { feature_.check_run_options(); }
  void register_components(ecs::ComponentRegistry& registry) override;
  void register_systems(ecs::Scheduler& s) override;
  void on_level_loaded(ecs::World& world, const scene::LevelInfo& level) override;
  void extract(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) override { feature_.extract(world, snapshot); }
  void create_gpu(cumulo::render::GpuServices& g) override { feature_.create_gpu(g); }
  void destroy_gpu() override { feature_.destroy_gpu(); }
  void add_passes(cumulo::render::Stage stage, cumulo::render::StageContext& f) override { feature_.add_passes(stage, f); }

  render::CloudFeature& feature() { return feature_; }

 private:
  render::CloudFeature feature_;
};

std::shared_ptr<app::Module> make_clouds_module();

}  // namespace cumulo::clouds
