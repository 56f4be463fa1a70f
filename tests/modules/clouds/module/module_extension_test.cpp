// Issue 22's promise, kept as a test: a simulation-only component with its system enters through a
// module of its own (here a strike counter beside the clouds module) and touches nothing of the clouds'
// rendering: the level names the component, the system reads the clouds' gameplay (LightningEvent) from
// the world, and no GPU exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "engine/app/simulation.h"
#include "engine/core/file_io.h"
#include "modules/clouds/clouds_module.h"
#include "modules/clouds/gameplay/lightning.h"
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
