// Determinism of the cloud module's simulation through a recording (issue 9: "a replay of the same
// inputs and seed gives the same weather, lightning and dissipation, frame for frame"; `cumulo run
// --record / --replay`): the sample level simulated for 10 minutes at 60 Hz without rendering, with
// inputs (the viewer flies from the overview camera into the storm cloud from 4 to 5 min, which starts
// the encounter and its lightning through the level's trigger; `stormbird_killed` is scheduled at 7 min),
// recorded to a file; a replay of that file gives the same state hash after every step; another seed
// does not.
#include <gtest/gtest.h>

#include <vector>

#include "engine/app/game_events.h"
#include "engine/app/recording.h"
#include "engine/app/simulation.h"
#include "engine/scene/camera.h"
#include "engine/scene/components.h"
#include "modules/clouds/clouds_module.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/state_hash.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;

namespace {

constexpr int kSteps = 10 * 60 * 60;

struct SimRun {
  std::vector<uint64_t> hashes;
  uint32_t transitions = 0;
  size_t max_flashes = 0;
  bool encounter = false;
  float dissipation = 0.0f;
  int strikes_fight = 0, strikes_after = 0;  // flashes spawned in the storm cloud: 5-7 min, 7.5-10 min
};

std::unique_ptr<app::Simulation> make_sim(uint64_t seed) {
  app::SimulationDesc d;
  d.level = "content/levels/sample/level.json";
  d.seed = seed;
  d.modules = {clouds::make_clouds_module()};
  auto sim = std::make_unique<app::Simulation>(d);
  sim->world().set_resource<app::Viewer>(app::Viewer{sim->camera("overview")});
  return sim;
}

// `live`: the inputs are given here (the recorded run); otherwise the replay attached to `sim` gives them.
SimRun simulate(app::Simulation& sim, bool live) {
  ecs::World& w = sim.world();
  const ecs::Entity viewer = w.resource<app::Viewer>().entity;
  const glm::vec3 from = w.get<scene::Transform>(viewer).position, to(1090, 860, -700);  // into the chamber
  if (live) app::schedule_event(w, "stormbird_killed", 7 * 60.0);
  SimRun r;
  r.hashes.reserve(kSteps);
  for (int i = 0; i < kSteps; ++i) {
    if (live && i >= 4 * 3600 && i <= 5 * 3600)
      w.get<scene::Transform>(viewer).position = glm::mix(from, to, float(i - 4 * 3600) / 3600.0f);
    sim.step(1);
    r.hashes.push_back(clouds::gameplay::cloud_state_hash(w));
    size_t flashes = 0;
    w.view<const clouds::gameplay::LightningEvent>().each([&](const clouds::gameplay::LightningEvent& l) {
      ++flashes;
      const bool fresh = l.age_s == 0.0f, in_storm = glm::distance(l.position, glm::vec3(1000, 830, -700)) < 300.0f;
      if (fresh && in_storm && i >= 5 * 3600 && i < 7 * 3600) ++r.strikes_fight;
      if (fresh && in_storm && i >= 7 * 3600 + 1800) ++r.strikes_after;
    });
    r.max_flashes = std::max(r.max_flashes, flashes);
    w.view<const clouds::weather::WeatherScheduler>().each(
        [&](const clouds::weather::WeatherScheduler& s) { r.encounter |= s.encounter_active; });
  }
  w.view<const clouds::weather::WeatherScheduler>().each(
      [&](const clouds::weather::WeatherScheduler& s) { r.transitions = s.transitions; });
  w.view<const clouds::gameplay::StormbirdDissipation>().each(
      [&](const clouds::gameplay::StormbirdDissipation& d) { r.dissipation = d.progress; });
  return r;
}

size_t first_difference(const SimRun& a, const SimRun& b) {
  for (size_t i = 0; i < a.hashes.size() && i < b.hashes.size(); ++i)
    if (a.hashes[i] != b.hashes[i]) return i;
  return a.hashes.size() == b.hashes.size() ? a.hashes.size() : std::min(a.hashes.size(), b.hashes.size());
}

TEST(CloudReplay, ARecordingReplaysTheSameStateEveryStepForTenMinutes) {
  const test::TempDir tmp(test::test_temp_name("cumulo_replay"));
  const std::filesystem::path file = tmp.path / "ten_minutes.json";
  auto recorded_sim = make_sim(7);
  app::start_recording(*recorded_sim, {"content/levels/sample/level.json", 7, 60, std::nullopt, "overview"});
  const SimRun a = simulate(*recorded_sim, true);
  const app::Recording rec = app::finish_recording(*recorded_sim);
  app::save_recording(file, rec);
  EXPECT_EQ(rec.steps, uint64_t(kSteps));
  EXPECT_GE(rec.camera_path.size(), 3600u);  // the flight: a pose per step
  ASSERT_EQ(rec.events.size(), 1u);
  EXPECT_EQ(rec.events[0].name, "stormbird_killed");
  std::printf("  10 min: %u weather transitions, up to %zu flashes at once, dissipation %.2f\n", a.transitions,
              a.max_flashes, a.dissipation);
  EXPECT_TRUE(a.encounter);            // the trigger fired on entering the storm cloud
  EXPECT_GE(a.transitions, 1u);        // so the hash covered a transition
  EXPECT_GE(a.max_flashes, 1u);        // and lightning
  EXPECT_FLOAT_EQ(a.dissipation, 1.0f);  // and the whole dissipation
  // The fight's lightning strikes in the storm cloud (stormbird: 12 a minute) and stops with its death.
  std::printf("  strikes in the storm cloud: %d in the 2 min of the fight, %d in the 2.5 min after its death\n",
              a.strikes_fight, a.strikes_after);
  EXPECT_GE(a.strikes_fight, 8);
  EXPECT_LE(a.strikes_after, a.strikes_fight / 8);

  auto replay_sim = make_sim(7);
  app::start_replay(*replay_sim, app::load_recording(file));
  const SimRun b = simulate(*replay_sim, false);
  EXPECT_EQ(first_difference(a, b), a.hashes.size()) << "the replay parts from the recording at step " << first_difference(a, b);

  auto other_seed = make_sim(8);
  app::start_replay(*other_seed, app::load_recording(file));
  const SimRun c = simulate(*other_seed, false);
  EXPECT_NE(a.hashes.back(), c.hashes.back());
}

}  // namespace
