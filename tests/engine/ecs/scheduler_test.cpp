// Systems in phases, fixed steps, deferred commands between systems, events across systems.
#include "engine/ecs/scheduler.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/ecs/world.h"
#include "tests/engine/ecs/components.h"
#include "tests/engine/ecs/expect_error.h"

namespace cumulo::ecs {
namespace {
using namespace test;

TEST(Scheduler, RunsPhasesInOrderThenInsertionOrder) {
  World w;
  Scheduler s;
  std::vector<std::string> log;
  auto sys = [&log](std::string name) { return [&log, name](World&, const FrameContext&) { log.push_back(name); }; };
  s.add_system(Phase::Extract, "extract", sys("extract"));
  s.add_system(Phase::Update, "update1", sys("update1"));
  s.add_system(Phase::Input, "input", sys("input"));
  s.add_system(Phase::Update, "update2", sys("update2"));
  s.add_system(Phase::PostUpdate, "post", sys("post"));
  s.add_system(Phase::PreUpdate, "pre", sys("pre"));
  s.add_system(Phase::Update, "update3", sys("update3"));
  s.tick(w, 1.0 / 60.0);
  EXPECT_EQ(log, (std::vector<std::string>{"input", "pre", "update1", "update2", "update3", "post", "extract"}));
  ASSERT_EQ(s.systems().size(), 7u);
  EXPECT_EQ(s.systems().front().name, "input");
  EXPECT_EQ(std::string(phase_name(s.systems().back().phase)), "Extract");

  log.clear();
  s.step(w, 1.0 / 60.0);  // simulation only
  EXPECT_EQ(log.back(), "post");
  log.clear();
  s.extract(w);
  EXPECT_EQ(log, (std::vector<std::string>{"extract"}));
}

TEST(Scheduler, FixedStepContext) {
  World w;
  Scheduler s;
  std::vector<FrameContext> seen;
  s.add_system(Phase::Update, "record", [&](World&, const FrameContext& f) { seen.push_back(f); });
  for (int i = 0; i < 3; ++i) s.step(w, 0.25);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[2].step, 2u);
  EXPECT_DOUBLE_EQ(seen[2].dt, 0.25);
  EXPECT_DOUBLE_EQ(seen[2].time, 0.5);
  EXPECT_DOUBLE_EQ(s.time(), 0.75);
  EXPECT_EQ(s.steps(), 3u);
}

TEST(Scheduler, DeferredCommandsAreAppliedBetweenSystems) {
  World w;
  Scheduler s;
  Entity spawned;
  s.add_system(Phase::Update, "spawn", [&](World& world, const FrameContext&) {
    spawned = world.defer().create();
    world.defer().emplace<Health>(spawned, 5);
  });
  bool saw = false;
  s.add_system(Phase::Update, "see", [&](World& world, const FrameContext&) { saw = world.valid(spawned); });
  s.step(w, 0.1);
  EXPECT_TRUE(saw);
}

struct LightningTriggered {
  int strength = 0;
};

TEST(Scheduler, SystemsReactToEventsOnceEach) {
  World w;
  Scheduler s;
  std::vector<int> heard;
  // The listener runs BEFORE the emitter in the phase order, so it hears each strike one step later.
  s.add_system(Phase::PreUpdate, "thunder",
               [&heard, reader = EventReader<LightningTriggered>{}](World& world, const FrameContext&) mutable {
                 for (const LightningTriggered& ev : world.read(reader)) heard.push_back(ev.strength);
               });
  s.add_system(Phase::Update, "storm", [](World& world, const FrameContext& f) {
    if (f.step % 2 == 0) world.emit(LightningTriggered{int(f.step)});
  });
  for (int i = 0; i < 6; ++i) s.step(w, 0.1);
  EXPECT_EQ(heard, (std::vector<int>{0, 2, 4}));
}

TEST(Scheduler, ErrorsNameTheSystem) {
  World w;
  Scheduler s;
  s.add_system(Phase::Update, "broken", [](World& world, const FrameContext&) { world.get<Health>(Entity{}); });
  EXPECT_ERROR_HAS(s.step(w, 0.1), "system 'broken' (Update)");
  EXPECT_ERROR_HAS(s.add_system(Phase::Input, "broken", [](World&, const FrameContext&) {}), "already exists");
  EXPECT_ERROR_HAS(s.add_system(Phase::Input, "", [](World&, const FrameContext&) {}), "empty system name");
  EXPECT_ERROR_HAS(s.set_enabled("nope", false), "no system named");
}

TEST(Scheduler, DisableAndRemoveSystems) {
  World w;
  Scheduler s;
  int a = 0, b = 0;
  s.add_system(Phase::Update, "a", [&](World&, const FrameContext&) { ++a; });
  s.add_system(Phase::Update, "b", [&](World&, const FrameContext&) { ++b; });
  s.set_enabled("a", false);
  s.step(w, 0.1);
  EXPECT_EQ(a, 0);
  EXPECT_EQ(b, 1);
  EXPECT_TRUE(s.remove_system("b"));
  EXPECT_FALSE(s.remove_system("b"));
  s.set_enabled("a", true);
  s.step(w, 0.1);
  EXPECT_EQ(a, 1);
  EXPECT_EQ(b, 1);
}

TEST(Scheduler, SystemMayRemoveItself) {
  World w;
  Scheduler s;
  int runs = 0;
  s.add_system(Phase::Update, "once", [&](World&, const FrameContext&) {
    ++runs;
    s.remove_system("once");
  });
  s.step(w, 0.1);
  s.step(w, 0.1);
  EXPECT_EQ(runs, 1);
}

}  // namespace
}  // namespace cumulo::ecs
