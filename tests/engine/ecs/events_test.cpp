// Typed, double-buffered events and per-reader cursors.
#include <gtest/gtest.h>

#include <vector>

#include "engine/ecs/world.h"

namespace cumulo::ecs {
namespace {

struct LightningTriggered {
  int id = 0;
};
struct Other {
  float v = 0;
};

std::vector<int> ids(EventRange<LightningTriggered> r) {
  std::vector<int> out;
  for (const LightningTriggered& ev : r) out.push_back(ev.id);
  return out;
}

TEST(Events, ReaderSeesEachEventOnceWhateverTheOrder) {
  World w;
  EventReader<LightningTriggered> early, late;  // run before / after the emitter within a step
  // step 0
  w.update_events();
  EXPECT_TRUE(w.read(early).empty());
  w.emit(LightningTriggered{1});
  w.emit(LightningTriggered{2});
  EXPECT_EQ(ids(w.read(late)), (std::vector<int>{1, 2}));
  // step 1: the early reader catches up on last step's events; the late one has seen them
  w.update_events();
  EXPECT_EQ(ids(w.read(early)), (std::vector<int>{1, 2}));
  w.emit(LightningTriggered{3});
  EXPECT_EQ(ids(w.read(late)), (std::vector<int>{3}));
  // step 2
  w.update_events();
  EXPECT_EQ(ids(w.read(early)), (std::vector<int>{3}));
  EXPECT_TRUE(w.read(late).empty());
  EXPECT_EQ(early.missed(), 0u);
  EXPECT_EQ(late.missed(), 0u);
}

TEST(Events, EventsLiveTwoStepsThenDrop) {
  World w;
  w.update_events();
  w.emit(LightningTriggered{1});
  EXPECT_EQ(w.events<LightningTriggered>().current().size(), 1u);
  w.update_events();
  EXPECT_EQ(w.events<LightningTriggered>().current().size(), 0u);
  EXPECT_EQ(w.events<LightningTriggered>().previous().size(), 1u);
  EXPECT_EQ(w.events<LightningTriggered>().all().size(), 1u);
  w.update_events();
  EXPECT_TRUE(w.events<LightningTriggered>().all().empty());
  // A reader that never ran lost the event and says so.
  EventReader<LightningTriggered> sleeper;
  EXPECT_TRUE(w.read(sleeper).empty());
  EXPECT_EQ(sleeper.missed(), 1u);
}

TEST(Events, TypesAreIndependent) {
  World w;
  w.emit(Other{2.5f});
  w.emit(LightningTriggered{7});
  EventReader<Other> r;
  auto got = w.read(r);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_FLOAT_EQ(got[0].v, 2.5f);
  EXPECT_EQ(w.events<LightningTriggered>().current()[0].id, 7);
}

TEST(Events, EmittingDuringIterationIsAllowed) {
  World w;
  for (int i = 0; i < 5; ++i) w.emplace<Other>(w.create(), float(i));
  w.view<const Other>().each([&](const Other& o) { w.emit(LightningTriggered{int(o.v)}); });
  EXPECT_EQ(w.events<LightningTriggered>().current().size(), 5u);
}

}  // namespace
}  // namespace cumulo::ecs
