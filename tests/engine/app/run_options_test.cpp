#include "engine/app/run_options.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.h"

using namespace cumulo;
using namespace cumulo::app;

static std::optional<RunOptions> parse(std::vector<std::string> args) {
  args.insert(args.begin(), "run");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return parse_run_options(static_cast<int>(argv.size()), argv.data());
}

// The error a parse throws, or "(accepted)".
static std::string message(std::vector<std::string> args) {
  try {
    parse(std::move(args));
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(RunOptions, ParsesEveryFlag) {
  auto o = parse({"level.json", "--headless", "--frames", "3", "--size", "320x180", "--mode", "40", "--screenshot",
                  "a.png", "--camera", "ground", "--time-of-day", "17.5", "--seed", "42", "--start-at", "2.5",
                  "--stats", "s.json", "--dump-graph", "g.dot"});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->level, "level.json");
  EXPECT_TRUE(o->headless);
  EXPECT_EQ(o->frames, 3u);
  EXPECT_EQ(o->width, 320u);
  EXPECT_EQ(o->height, 180u);
  EXPECT_EQ(o->mode, render::BudgetMode::Hz40);
  EXPECT_EQ(o->screenshot, "a.png");
  EXPECT_EQ(o->camera, "ground");
  ASSERT_TRUE(o->time_of_day);
  EXPECT_FLOAT_EQ(*o->time_of_day, 17.5f);
  EXPECT_EQ(o->seed, 42u);
  EXPECT_DOUBLE_EQ(o->start_at, 2.5);
  EXPECT_EQ(o->stats, "s.json");
  EXPECT_EQ(o->dump_graph, "g.dot");
}

TEST(RunOptions, HeadlessDefaultsToOneFrame) {
  auto o = parse({"l.json", "--headless"});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->frames, kDefaultHeadlessFrames);
  EXPECT_FALSE(o->time_of_day);
  EXPECT_EQ(o->mode, render::BudgetMode::Hz30);
}

TEST(RunOptions, BadValuesAreClearErrors) {
  EXPECT_NE(message({"l.json", "--size", "320by180"}).find("WIDTHxHEIGHT"), std::string::npos);
  EXPECT_NE(message({"l.json", "--size", "0x10"}).find("outside"), std::string::npos);
  EXPECT_NE(message({"l.json", "--mode", "50"}).find("30, 40 or 60"), std::string::npos);
  EXPECT_NE(message({"l.json", "--time-of-day", "25"}).find("0..24"), std::string::npos);
  EXPECT_NE(message({"l.json", "--frames", "many"}).find("--frames"), std::string::npos);
  EXPECT_NE(message({"l.json", "--bogus"}).find("unknown option"), std::string::npos);
  EXPECT_NE(message({}).find("missing LEVEL"), std::string::npos);
  // NaN passed the old range check and became ~9.2e18 fast-forward steps (a hang).
  EXPECT_NE(message({"l.json", "--start-at", "nan"}).find("--start-at: expected a finite number, got nan"), std::string::npos);
  EXPECT_NE(message({"l.json", "--start-at", "-1"}).find("--start-at: -1 is out of range"), std::string::npos);
  EXPECT_NE(message({"l.json", "--time-of-day", "nan"}).find("--time-of-day: expected a finite number"), std::string::npos);
  // 4294967312 used to wrap to 16.
  EXPECT_NE(message({"l.json", "--frames", "4294967312"}).find("--frames: 4294967312 does not fit"), std::string::npos);
  EXPECT_NE(message({"l.json", "--seed", "-1"}).find("--seed: -1 does not fit"), std::string::npos);
  EXPECT_NE(message({"l.json", "--sim-hz", "0"}).find("--sim-hz: 0 is out of range (expected 1..1000)"), std::string::npos);
}

TEST(RunOptions, BudgetAndResolutionFlags) {
  auto o = parse({"l.json"});
  ASSERT_TRUE(o);
  EXPECT_FALSE(o->dynamic_resolution) << "unset: the loop decides (on in a window, off headless)";
  EXPECT_FALSE(o->budget_scale);
  EXPECT_FALSE(o->resolution_scale);
  o = parse({"l.json", "--dynamic-resolution", "on", "--budget-scale", "2.5"});
  ASSERT_TRUE(o);
  EXPECT_EQ(o->dynamic_resolution, true);
  EXPECT_DOUBLE_EQ(o->budget_scale.value_or(0), 2.5);
  o = parse({"l.json", "--resolution-scale", "0.75"});
  ASSERT_TRUE(o);
  EXPECT_FLOAT_EQ(o->resolution_scale.value_or(0), 0.75f);
  EXPECT_NE(message({"l.json", "--resolution-scale", "0.5", "--dynamic-resolution", "on"}).find("not both"), std::string::npos);
  EXPECT_NE(message({"l.json", "--resolution-scale", "2"}).find("--resolution-scale: 2 is out of range"), std::string::npos);
  EXPECT_NE(message({"l.json", "--resolution-scale", "nan"}).find("finite"), std::string::npos);
  EXPECT_NE(message({"l.json", "--budget-scale", "0"}).find("--budget-scale: 0 is out of range"), std::string::npos);
  EXPECT_NE(message({"l.json", "--dynamic-resolution", "maybe"}).find("--dynamic-resolution"), std::string::npos);
}

TEST(RunOptions, SizeParser) {
  uint32_t w = 0, h = 0;
  parse_size("160x90", w, h);
  EXPECT_EQ(w, 160u);
  EXPECT_EQ(h, 90u);
  EXPECT_THROW(parse_size("160x", w, h), Error);
  EXPECT_THROW(parse_size("x90", w, h), Error);
  EXPECT_THROW(parse_size("16.5x90", w, h), Error);
}
