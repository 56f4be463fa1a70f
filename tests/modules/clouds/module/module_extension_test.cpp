// Issue 22's promises, kept as tests: a simulation-only component with its system enters through a
// module of its own (here a strike counter beside the clouds module) and touches nothing of the clouds'
// rendering: the level names the component, the system reads the clouds' gameplay (LightningEvent) from
// the world, and no GPU exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "engine/app/application.h"
#include "engine/app/run_options.h"
#include "engine/app/simulation.h"
#include "engine/core/file_io.h"
#include "modules/clouds/clouds_module.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/render/cloud_frame_pass.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
using namespace cumulo::clouds;

namespace {

struct StrikeCount {
  uint64_t strikes = 0;
  std::vector<ecs::Entity> live;  // the flashes seen last step
};

class StrikeCounterModule final : public app::Module {
 public:
  const char* name() const override { return "strike_counter"; }
  void register_components(ecs::ComponentRegistry& r) override {
    r.register_component<StrikeCount>(
        "StrikeCount", [](const StrikeCount& c) { return Json{{"strikes", c.strikes}}; },
        [](const JsonView& v) { return StrikeCount{v.get<uint64_t>("strikes", 0), {}}; });
  }
  void register_systems(ecs::Scheduler& s) override {
    s.add_system(ecs::Phase::Update, "strike counter", [](ecs::World& w, const ecs::FrameContext&) {
      std::vector<ecs::Entity> now;
      static_cast<const ecs::World&>(w).view<const gameplay::LightningEvent>().each(
          [&](ecs::Entity e, const gameplay::LightningEvent&) { now.push_back(e); });
      w.view<StrikeCount>().each([&](StrikeCount& c) {
        for (ecs::Entity e : now)
          if (std::find(c.live.begin(), c.live.end(), e) == c.live.end()) ++c.strikes;
        c.live = now;
      });
    });
  }
};

}  // namespace

TEST(ModuleExtension, ASimulationOnlyComponentCountsTheCloudsLightningWithoutTheRenderer) {
  test::TempDir tmp("cumulo_strike_counter");
  const auto level = tmp.path / "level.json";
  write_file_atomic(level, R"({"version": 1, "entities": [
      {"name": "counter", "components": {"StrikeCount": {}}},
      {"name": "flash", "components": {"Trigger": {"when": {"time": 0.1},
          "actions": [{"do": "strike_lightning", "position": [0, 900, 0]}]}}},
      {"name": "flash again", "components": {"Trigger": {"when": {"time": 0.5},
          "actions": [{"do": "strike_lightning", "position": [100, 900, 0]}]}}}]})");
  app::SimulationDesc d;
  d.level = level;
  d.modules = {std::make_shared<CloudsModule>(), std::make_shared<StrikeCounterModule>()};
  app::Simulation sim(d);
  sim.step(60);  // 1 s at 60 Hz: both triggers fire
  uint64_t strikes = 0;
  sim.world().view<const StrikeCount>().each([&](const StrikeCount& c) { strikes = c.strikes; });
  EXPECT_EQ(strikes, 2u);
}

// And a pass of the clouds' frame: its own class, one add_frame_pass (the built-in ones are one line each
// in render/cloud_frame_passes.cpp), and it runs after the clouds' passes with their outputs in hand.
namespace {

class MarkerPass final : public clouds::render::CloudFramePass {
 public:
  int* frames;
  explicit MarkerPass(int* f) : frames(f) {}
  bool create_gpu(cumulo::render::GpuServices&, const clouds::render::CloudRenderOptions&,
                  const clouds::render::CloudLevelFacts&) override {
    return true;
  }
  void destroy_gpu() override {}
  cumulo::render::TextureHandle add_passes(const clouds::render::CloudFramePassContext& c) override {
    EXPECT_TRUE(c.clouds.color.valid());
    EXPECT_FALSE(c.frame.instances.empty());
    ++*frames;
    cumulo::render::TextureHandle hdr = c.stage.hdr;
    const cumulo::render::TextureHandle clouds = c.clouds.color;
    c.stage.graph.add_pass("test.marker", cumulo::render::Queue::Compute,
                           [&](cumulo::render::PassBuilder& b) {
                             b.read(clouds, cumulo::render::Usage::Sampled);
                             hdr = b.read_write(hdr, cumulo::render::Usage::StorageWrite);
                           },
                           [](cumulo::render::PassContext&) {});
    return hdr;
  }
};

}  // namespace

TEST(ModuleExtension, AFramePassRunsAfterTheCloudsPassesWithTheirOutputs) {
  test::TempDir tmp("cumulo_frame_pass");
  std::filesystem::copy_file("tests/modules/clouds/module/data/small_cloud.json", tmp.path / "small_cloud.json");
  write_file_atomic(tmp.path / "level.json", read_file_text("tests/modules/clouds/module/data/level.json"));
  auto clouds = make_clouds_module();
  int frames = 0;
  clouds->feature().add_frame_pass(std::make_unique<MarkerPass>(&frames));
  const std::string dump = (tmp.path / "graph.txt").string(), level = (tmp.path / "level.json").string();
  std::vector<std::string> args{"run", level, "--headless", "--frames", "2", "--size", "160x90", "--dump-graph", dump};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  app::Modules modules{clouds};
  auto o = app::parse_run_options(int(argv.size()), argv.data(), modules);
  ASSERT_TRUE(o);
  EXPECT_EQ(app::run_level(*o, modules), 0);
  EXPECT_EQ(frames, 2);
  const std::string graph = read_file_text(dump);
  const size_t composite = graph.find("clouds.composite"), marker = graph.find("test.marker");
  ASSERT_NE(marker, std::string::npos) << graph;
  EXPECT_LT(composite, marker);
}
