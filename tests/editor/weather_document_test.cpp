// WeatherDocument in memory: edits, validation, undo/redo, painting, change and dirty tracking.
#include "editor/model/weather_document.h"

#include <gtest/gtest.h>

#include "editor/model/weather_params.h"
#include "tests/editor/editor_test_support.h"

namespace cumulo::editor {
namespace {

using Strings = std::vector<std::string>;

struct Fixture : ::testing::Test {
  cumulo::test::TempDir tmp{cumulo::test::test_temp_name("cumulo_editor_doc")};
  int maps_made = 0;
  WeatherDocument open() {
    return WeatherDocument::open(tmp.path, [this](const clouds::weather::CloudMapSource& s) {
      ++maps_made;
      return test::fake_map(s);
    });
  }
  void SetUp() override { test::copy_shipped_weather(tmp.path); }
};

std::string thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no throw)";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST_F(Fixture, OpensTheShippedStatesClean) {
  WeatherDocument doc = open();
  EXPECT_EQ(doc.ids(), (Strings{"clear", "fair_cumulus", "overcast_stratus", "storm", "stormbird"}));
  EXPECT_TRUE(doc.problems().empty());
  EXPECT_FALSE(doc.dirty());
  EXPECT_FALSE(doc.can_undo());
  EXPECT_EQ(doc.state("storm").id, "storm");
  EXPECT_EQ(doc.state("storm"), clouds::weather::load_weather_state(tmp.path / "storm.json"));
  EXPECT_TRUE(doc.take_changed().empty());
  EXPECT_TRUE(contains(thrown([&] { doc.json("nope"); }), "known: clear, fair_cumulus"));
}

TEST_F(Fixture, MalformedFileAtOpenIsListedAndSkipped) {
  write_file_atomic(tmp.path / "broken.json", R"({"coverage": 2})");
  write_file_atomic(tmp.path / "bad name.json", "{}");
  WeatherDocument doc = open();
  EXPECT_EQ(doc.ids().size(), 5u);
  ASSERT_EQ(doc.problems().size(), 2u);
  EXPECT_TRUE(contains(doc.problems()[0], "bad name.json")) << doc.problems()[0];
  EXPECT_TRUE(contains(doc.problems()[1], "broken.json")) << doc.problems()[1];
  EXPECT_TRUE(contains(doc.problems()[1], "$")) << doc.problems()[1];
  // Its name is not reused silently.
  EXPECT_TRUE(contains(thrown([&] { doc.create("broken"); }), "did not load"));
}

TEST_F(Fixture, SetUndoRedo) {
  WeatherDocument doc = open();
  const Json before = doc.json("fair_cumulus");
  doc.set("fair_cumulus", "coverage", 0.7);
  EXPECT_EQ(doc.json("fair_cumulus")["coverage"], 0.7);
  EXPECT_FLOAT_EQ(doc.state("fair_cumulus").coverage, 0.7f);
  EXPECT_TRUE(doc.dirty());
  EXPECT_TRUE(doc.dirty("fair_cumulus"));
  EXPECT_FALSE(doc.dirty("storm"));
  EXPECT_EQ(doc.undo_label(), "set coverage of fair_cumulus");
  EXPECT_EQ(doc.take_changed(), Strings{"fair_cumulus"});
  EXPECT_TRUE(doc.take_changed().empty());
  doc.set("fair_cumulus", "lighting.phase.forward", 0.5);
  doc.undo();
  doc.undo();
  EXPECT_EQ(doc.json("fair_cumulus"), before);
  EXPECT_FALSE(doc.dirty());  // back at the saved state
  EXPECT_FALSE(doc.can_undo());
  EXPECT_EQ(doc.redo_label(), "set coverage of fair_cumulus");
  doc.redo();
  EXPECT_EQ(doc.json("fair_cumulus")["coverage"], 0.7);
  EXPECT_EQ(doc.redo_label(), "set lighting.phase.forward of fair_cumulus");
  doc.set("fair_cumulus", "haze", 0.2);  // a new edit drops the redo
  EXPECT_FALSE(doc.can_redo());
  // Setting the current value is no step.
  doc.set("fair_cumulus", "haze", 0.2);
  doc.undo();
  EXPECT_EQ(doc.json("fair_cumulus")["haze"], before["haze"]);
}

TEST_F(Fixture, MergedSetsAreOneStep) {
  WeatherDocument doc = open();
  const Json start = doc.json("storm")["coverage"];
  for (float v : {0.1f, 0.2f, 0.3f}) doc.set("storm", "coverage", v, true);
  EXPECT_EQ(doc.json("storm")["coverage"].dump(), "0.3");  // a float slider's value, stored short
  doc.set("storm", "haze", 0.3, true);                     // another parameter: its own step
  doc.undo();
  doc.undo();
  EXPECT_EQ(doc.json("storm")["coverage"], start);
  EXPECT_FALSE(doc.can_undo());
  // A drag that ends where it began leaves nothing to undo.
  doc.set("storm", "coverage", 0.5, true);
  doc.set("storm", "coverage", start, true);
  EXPECT_FALSE(doc.can_undo());
  EXPECT_FALSE(doc.dirty());
  // Unmerged sets are separate steps.
  doc.set("storm", "coverage", 0.5, true);
  doc.set("storm", "coverage", 0.6);
  doc.undo();
  EXPECT_EQ(doc.json("storm")["coverage"], 0.5);
}

TEST_F(Fixture, BadValuesAreRefusedAndChangeNothing) {
  WeatherDocument doc = open();
  const Json before = doc.json("fair_cumulus");
  std::string m = thrown([&] { doc.set("fair_cumulus", "coverage", 1.5); });
  EXPECT_EQ(m, "fair_cumulus: coverage: 1.5 is out of range [0, 1]");
  m = thrown([&] { doc.set("fair_cumulus", "lighting.absorption", 0.0); });
  EXPECT_TRUE(contains(m, "lighting.absorption") && contains(m, "[1e-05, 10]")) << m;
  m = thrown([&] { doc.set("fair_cumulus", "wind.direction", Json::array({0, 0, 0})); });  // the loader's rule
  EXPECT_TRUE(contains(m, "fair_cumulus") && contains(m, "wind.direction") && contains(m, "non-zero")) << m;
  m = thrown([&] { doc.set("fair_cumulus", "colour", 1); });
  EXPECT_TRUE(contains(m, "unknown parameter \"colour\"")) << m;
  m = thrown([&] { doc.set("fair_cumulus", "cloud_map.procedural.octaves", 2.5); });
  EXPECT_TRUE(contains(m, "expected an integer in [1, 8]")) << m;
  EXPECT_THROW(doc.set("nope", "coverage", 0.1), Error);
  EXPECT_EQ(doc.json("fair_cumulus"), before);
  EXPECT_FALSE(doc.dirty());
  EXPECT_FALSE(doc.can_undo());
  EXPECT_TRUE(doc.take_changed().empty());
}

TEST_F(Fixture, CreateDuplicateRenameRemoveUndo) {
  WeatherDocument doc = open();
  doc.create("calm");
  EXPECT_FLOAT_EQ(doc.state("calm").coverage, 0.0f);
  EXPECT_EQ(doc.json("calm")["$schema"], "../schemas/weather.schema.json");
  doc.create("stormy", "storm");
  EXPECT_EQ(doc.json("stormy")["coverage"], doc.json("storm")["coverage"]);
  EXPECT_FALSE(doc.json("stormy").contains("description"));
  doc.duplicate("storm", "storm2");
  EXPECT_EQ(doc.json("storm2"), doc.json("storm"));
  EXPECT_EQ(doc.state("storm2").id, "storm2");
  EXPECT_EQ(doc.undo_label(), "duplicate storm as storm2");
  doc.take_changed();
  doc.rename("storm2", "storm_b");
  EXPECT_FALSE(doc.has("storm2"));
  EXPECT_TRUE(doc.has("storm_b"));
  EXPECT_EQ(doc.take_changed(), (Strings{"storm2", "storm_b"}));
  doc.remove("clear");
  EXPECT_FALSE(doc.has("clear"));
  EXPECT_TRUE(doc.dirty("clear"));
  EXPECT_EQ(doc.undo_label(), "delete clear");
  // Refusals.
  EXPECT_TRUE(contains(thrown([&] { doc.create("storm"); }), "exists"));
  EXPECT_TRUE(contains(thrown([&] { doc.create("a/b"); }), "letters, digits"));
  EXPECT_TRUE(contains(thrown([&] { doc.create(""); }), "letters, digits"));
  EXPECT_TRUE(contains(thrown([&] { doc.rename("storm", "fair_cumulus"); }), "exists"));
  EXPECT_TRUE(contains(thrown([&] { doc.duplicate("gone", "x"); }), "unknown weather state"));
  EXPECT_TRUE(contains(thrown([&] { doc.create("x", "gone"); }), "unknown weather state"));
  // All the way back.
  for (int i = 0; i < 5; ++i) doc.undo();
  EXPECT_EQ(doc.ids(), (Strings{"clear", "fair_cumulus", "overcast_stratus", "storm", "stormbird"}));
  EXPECT_FALSE(doc.dirty());
  for (int i = 0; i < 5; ++i) doc.redo();
  EXPECT_EQ(doc.ids(),
            (Strings{"calm", "fair_cumulus", "overcast_stratus", "storm", "storm_b", "stormbird", "stormy"}));
}

TEST_F(Fixture, PaintStrokesAreUndoStepsThatRestorePixelsExactly) {
  WeatherDocument doc = open();
  EXPECT_EQ(doc.state("storm").cloud_map.painted, nullptr);
  doc.begin_stroke("storm");
  doc.paint("storm", MapChannel::Coverage, {0.5f, 0.5f}, 0.1f, 0.0f);
  const auto first = doc.state("storm").cloud_map.painted;
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(maps_made, 1);  // the base came from the map maker
  doc.paint_line("storm", MapChannel::Coverage, {0.5f, 0.5f}, {0.9f, 0.5f}, 0.1f, 0.0f);
  const auto second = doc.state("storm").cloud_map.painted;
  EXPECT_NE(second, first);  // a new map per change: the renderer compares pointers
  EXPECT_EQ(first->rgba.size(), second->rgba.size());
  EXPECT_NE(first->rgba, second->rgba);
  EXPECT_EQ(doc.undo_label(), "paint storm");  // while the stroke is open
  doc.end_stroke();
  const std::vector<uint8_t> after_one = second->rgba;
  EXPECT_TRUE(doc.dirty("storm"));

  doc.paint("storm", MapChannel::Type, {0.1f, 0.1f}, 0.2f, 1.0f, 0.5f);  // begins a stroke by itself
  doc.end_stroke();
  EXPECT_EQ(maps_made, 1);  // later strokes start from the painting
  const auto two = doc.state("storm").cloud_map.painted;
  doc.undo();
  EXPECT_EQ(doc.state("storm").cloud_map.painted->rgba, after_one);
  doc.undo();
  EXPECT_EQ(doc.state("storm").cloud_map.painted, nullptr);
  EXPECT_FALSE(doc.dirty());
  doc.redo();
  doc.redo();
  EXPECT_EQ(doc.state("storm").cloud_map.painted->rgba, two->rgba);
  EXPECT_EQ(doc.take_changed(), Strings{"storm"});
  // Settings keep the painting; an empty stroke is no step.
  doc.set("storm", "coverage", 0.2);
  EXPECT_EQ(doc.state("storm").cloud_map.painted, two);
  doc.begin_stroke("storm");
  doc.end_stroke();
  EXPECT_EQ(doc.undo_label(), "set coverage of storm");
  EXPECT_THROW(doc.paint("storm", MapChannel::Coverage, {0.5f, 0.5f}, 0.0f, 0.0f), Error);
}

TEST_F(Fixture, ADuplicateSharesThePaintingUntilPainted) {
  WeatherDocument doc = open();
  doc.paint("clear", MapChannel::Coverage, {0.5f, 0.5f}, 0.3f, 1.0f);
  doc.duplicate("clear", "clear2");
  EXPECT_EQ(doc.state("clear2").cloud_map.painted, doc.state("clear").cloud_map.painted);
  doc.paint("clear2", MapChannel::Coverage, {0.1f, 0.5f}, 0.3f, 0.0f);
  EXPECT_NE(doc.state("clear2").cloud_map.painted->rgba, doc.state("clear").cloud_map.painted->rgba);
}

}  // namespace
}  // namespace cumulo::editor
