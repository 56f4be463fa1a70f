// WeatherDocument and the disk: saving (all or nothing, .bak copies, paintings) and the watch on
// changes made by others.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include "editor/model/weather_document.h"
#include "engine/core/file_io.h"
#include "engine/core/png.h"
#include "modules/clouds/weather/weather_state.h"
#include "tests/editor/editor_test_support.h"

namespace cumulo::editor {
namespace {

namespace fs = std::filesystem;
using clouds::weather::load_weather_state;
using clouds::weather::WeatherState;
using Kind = DiskEvent::Kind;

struct DiskFixture : ::testing::Test {
  cumulo::test::TempDir tmp{cumulo::test::test_temp_name("cumulo_editor_disk")};
  void SetUp() override { test::copy_shipped_weather(tmp.path); }
  WeatherDocument open() { return WeatherDocument::open(tmp.path, test::fake_map); }
  fs::path at(const std::string& name) const { return tmp.path / name; }
  std::string text(const std::string& name) const { return read_file_text(at(name)); }
};

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

WeatherState without_painting(WeatherState s) {
  s.cloud_map.painted = nullptr;
  return s;
}

TEST_F(DiskFixture, SaveWritesWhatReloadsWithABackup) {
  WeatherDocument doc = open();
  const std::string original = text("fair_cumulus.json");
  const std::string storm = text("storm.json");
  doc.set("fair_cumulus", "coverage", 0.55);
  doc.set("fair_cumulus", "wind.direction", Json::array({0, 0, 1}));
  doc.save();
  EXPECT_FALSE(doc.dirty());
  EXPECT_EQ(text("fair_cumulus.json.bak"), original);
  EXPECT_EQ(text("storm.json"), storm);  // clean states are not rewritten
  EXPECT_FALSE(fs::exists(at("storm.json.bak")));
  EXPECT_FALSE(fs::exists(at("fair_cumulus.json.tmp")));
  EXPECT_EQ(load_weather_state(at("fair_cumulus.json")), doc.state("fair_cumulus"));
  const std::string saved = text("fair_cumulus.json");
  EXPECT_EQ(saved.rfind("{\n  \"$schema\": \"../schemas/weather.schema.json\",\n  \"coverage\": 0.55,", 0), 0u)
      << saved;
  // Undo after a save is dirty again; saving that restores the original bytes.
  doc.undo();
  doc.undo();
  EXPECT_TRUE(doc.dirty("fair_cumulus"));
  doc.save();
  EXPECT_EQ(text("fair_cumulus.json"), original);
  EXPECT_EQ(text("fair_cumulus.json.bak"), saved);
  EXPECT_TRUE(doc.poll_disk().empty());  // our own writes are no news
}

TEST_F(DiskFixture, SaveWritesThePaintingBesideTheState) {
  WeatherDocument doc = open();
  doc.paint("storm", MapChannel::Coverage, {0.25f, 0.5f}, 0.2f, 0.0f);
  doc.paint("storm", MapChannel::Precipitation, {0.5f, 0.5f}, 0.2f, 1.0f);
  doc.end_stroke();
  const auto painted = doc.state("storm").cloud_map.painted;
  doc.take_changed();
  doc.save();
  EXPECT_EQ(doc.json("storm")["cloud_map"]["png"], "storm.cloud_map.png");
  const ImageRgba8 png = read_png_rgba8(at("storm.cloud_map.png"));
  EXPECT_EQ(png.width, painted->width);
  EXPECT_EQ(png.rgba, painted->rgba);
  const WeatherState loaded = load_weather_state(at("storm.json"));
  EXPECT_EQ(loaded.cloud_map.png, at("storm.cloud_map.png"));
  EXPECT_EQ(loaded, without_painting(doc.state("storm")));
  EXPECT_EQ(doc.state("storm").cloud_map.painted, painted);          // the same pixels stay in memory
  EXPECT_EQ(doc.take_changed(), std::vector<std::string>{"storm"});  // its png path changed
  EXPECT_FALSE(doc.dirty());
  // A second painting keeps the first PNG as .bak; a later open starts from the PNG.
  doc.paint("storm", MapChannel::Type, {0.5f, 0.5f}, 0.3f, 0.0f);
  doc.save();
  EXPECT_EQ(read_png_rgba8(at("storm.cloud_map.png.bak")).rgba, painted->rgba);
  WeatherDocument again = open();
  again.paint("storm", MapChannel::Type, {0.0f, 0.0f}, 0.01f, 0.0f, 0.0f);  // a dab that changes nothing
  EXPECT_EQ(again.state("storm").cloud_map.painted->rgba, doc.state("storm").cloud_map.painted->rgba);
}

TEST_F(DiskFixture, SaveRetiresRemovedAndRenamedStatesToBak) {
  WeatherDocument doc = open();
  const std::string clear = text("clear.json");
  const std::string storm = text("storm.json");
  doc.remove("clear");
  doc.rename("storm", "big_storm");
  doc.save();
  EXPECT_FALSE(fs::exists(at("clear.json")));
  EXPECT_EQ(text("clear.json.bak"), clear);
  EXPECT_FALSE(fs::exists(at("storm.json")));
  EXPECT_EQ(text("storm.json.bak"), storm);
  EXPECT_EQ(text("big_storm.json"), storm);
  EXPECT_FALSE(doc.dirty());
  EXPECT_TRUE(doc.poll_disk().empty());
  EXPECT_EQ(WeatherDocument::open(tmp.path, test::fake_map).ids(), doc.ids());
}

TEST_F(DiskFixture, RenamingAPaintedStateMovesItsPainting) {
  WeatherDocument doc = open();
  doc.paint("storm", MapChannel::Coverage, {0.5f, 0.5f}, 0.2f, 0.0f);
  doc.save();
  const std::vector<uint8_t> pixels = doc.state("storm").cloud_map.painted->rgba;
  doc.rename("storm", "big_storm");
  doc.save();
  EXPECT_EQ(doc.json("big_storm")["cloud_map"]["png"], "big_storm.cloud_map.png");
  EXPECT_EQ(read_png_rgba8(at("big_storm.cloud_map.png")).rgba, pixels);
  EXPECT_FALSE(fs::exists(at("storm.cloud_map.png")));
  EXPECT_TRUE(fs::exists(at("storm.cloud_map.png.bak")));
  EXPECT_EQ(load_weather_state(at("big_storm.json")), without_painting(doc.state("big_storm")));
}

TEST_F(DiskFixture, SaveRefusesAStateThatWouldNotLoad) {
  // A state whose PNG was deleted behind the editor's back: writing it would give a file that fails.
  WeatherDocument doc = open();
  doc.paint("clear", MapChannel::Coverage, {0.5f, 0.5f}, 0.2f, 0.0f);
  doc.save();
  WeatherDocument other = open();
  other.set("clear", "haze", 0.5);
  other.set("storm", "haze", 0.5);
  const std::string clear = text("clear.json"), storm = text("storm.json");
  fs::remove(at("clear.cloud_map.png"));
  std::string message;
  try {
    other.save();
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_TRUE(contains(message, "clear.json would not load")) << message;
  EXPECT_TRUE(contains(message, "$.cloud_map.png: no such file")) << message;
  EXPECT_EQ(text("clear.json"), clear);
  EXPECT_EQ(text("storm.json"), storm);  // all or nothing
  EXPECT_TRUE(other.dirty("storm"));
}

// Makes saving `file` fail the way a read-only folder does. Root ignores permissions, so the
// temporary's name is taken by a folder instead: the write fails with a real OS error either way.
void block_writes(const fs::path& dir, const fs::path& file) {
  fs::path tmp = file;
  tmp += ".tmp";
  fs::create_directory(tmp);
  if (!test::running_as_root()) ::chmod(dir.c_str(), 0555);
}

void unblock_writes(const fs::path& dir, const fs::path& file) {
  ::chmod(dir.c_str(), 0755);
  fs::path tmp = file;
  tmp += ".tmp";
  fs::remove(tmp);
}

TEST_F(DiskFixture, FailedSaveChangesNoFileAndKeepsTheEdits) {
  WeatherDocument doc = open();
  const std::string clear = text("clear.json"), fair = text("fair_cumulus.json"), storm = text("storm.json");
  doc.paint("clear", MapChannel::Coverage, {0.5f, 0.5f}, 0.2f, 1.0f);  // written before the JSON
  doc.set("fair_cumulus", "coverage", 0.9);
  doc.set("storm", "haze", 0.3);
  doc.remove("stormbird");
  const Json edited = doc.json("storm");
  const auto listing = [&] {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(tmp.path)) names.insert(e.path().filename().string());
    return names;
  };
  block_writes(tmp.path, at("storm.json"));
  const auto before = listing();
  std::string message;
  try {
    doc.save();
  } catch (const Error& e) {
    message = e.what();
  }
  unblock_writes(tmp.path, at("storm.json"));
  // As root the folder in the temporary's place fails storm.json; otherwise the first file written fails.
  EXPECT_TRUE(
      contains(message, test::running_as_root() ? "storm.json.tmp: cannot write: Is a directory" : "Permission denied"))
      << message;
  EXPECT_EQ(text("clear.json"), clear);
  EXPECT_EQ(text("fair_cumulus.json"), fair);
  EXPECT_EQ(text("storm.json"), storm);
  EXPECT_TRUE(fs::exists(at("stormbird.json")));
  auto after = listing();
  after.insert("storm.json.tmp");
  EXPECT_EQ(after, before);  // no temporaries, no .bak, no PNG left behind
  EXPECT_EQ(doc.json("storm"), edited);
  EXPECT_EQ(doc.dirty_ids(), (std::vector<std::string>{"clear", "fair_cumulus", "storm", "stormbird"}));
  EXPECT_NE(doc.state("clear").cloud_map.painted, nullptr);
  // Once the folder takes writes again the same save goes through.
  doc.save();
  EXPECT_FALSE(doc.dirty());
  EXPECT_FLOAT_EQ(load_weather_state(at("storm.json")).haze, 0.3f);
}

TEST_F(DiskFixture, ExternalEditReloadsACleanState) {
  WeatherDocument doc = open();
  doc.set("storm", "haze", 0.3);
  doc.set("clear", "haze", 0.3);
  doc.undo();  // clear is clean again, with a redo step
  doc.take_changed();
  EXPECT_TRUE(doc.poll_disk().empty());
  Json j = Json::parse(text("clear.json"));
  j["coverage"] = 0.25;
  test::external_write(at("clear.json"), weather_state_text(j));
  const auto events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Reloaded);
  EXPECT_EQ(events[0].id, "clear");
  EXPECT_FLOAT_EQ(doc.state("clear").coverage, 0.25f);
  EXPECT_FALSE(doc.dirty("clear"));
  EXPECT_EQ(doc.take_changed(), std::vector<std::string>{"clear"});
  EXPECT_FALSE(doc.can_redo());  // the redo step of clear is gone
  EXPECT_TRUE(doc.can_undo());   // storm's step is newer than anything of clear's: kept
  doc.undo();
  EXPECT_FALSE(doc.dirty());
  EXPECT_FLOAT_EQ(doc.state("clear").coverage, 0.25f);
  // Same text with a new mtime: nothing.
  test::external_write(at("clear.json"), text("clear.json"));
  EXPECT_TRUE(doc.poll_disk().empty());
}

TEST_F(DiskFixture, ExternalEditOfADirtyStateIsAConflict) {
  WeatherDocument doc = open();
  doc.set("storm", "haze", 0.3);
  Json j = Json::parse(text("storm.json"));
  j["coverage"] = 0.11;
  test::external_write(at("storm.json"), weather_state_text(j));
  auto events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Conflict);
  EXPECT_FLOAT_EQ(doc.state("storm").haze, 0.3f);  // mine is kept
  EXPECT_EQ(doc.conflicts(), std::vector<std::string>{"storm"});
  EXPECT_TRUE(doc.poll_disk().empty());  // reported once
  doc.resolve_conflict("storm", /*take_disk=*/true);
  EXPECT_FLOAT_EQ(doc.state("storm").coverage, 0.11f);
  EXPECT_FALSE(doc.dirty());
  EXPECT_FALSE(doc.can_undo());
  EXPECT_TRUE(doc.conflicts().empty());
  EXPECT_THROW(doc.resolve_conflict("storm", true), Error);

  // Keeping mine: it stays dirty against the disk and the next save writes it.
  doc.set("storm", "haze", 0.35);
  j["coverage"] = 0.12;
  test::external_write(at("storm.json"), weather_state_text(j));
  events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Conflict) << events[0].message;
  doc.resolve_conflict("storm", false);
  EXPECT_TRUE(doc.dirty("storm"));
  doc.save();
  EXPECT_FLOAT_EQ(load_weather_state(at("storm.json")).haze, 0.35f);
  EXPECT_FLOAT_EQ(load_weather_state(at("storm.json")).coverage, 0.11f);
}

TEST_F(DiskFixture, MalformedFileKeepsTheLastGoodState) {
  WeatherDocument doc = open();
  const WeatherState good = doc.state("fair_cumulus");
  Json j = Json::parse(text("fair_cumulus.json"));
  j["lighting"]["phase"]["forward"] = 3;
  test::external_write(at("fair_cumulus.json"), weather_state_text(j));
  auto events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Malformed);
  EXPECT_TRUE(contains(events[0].message, "fair_cumulus.json")) << events[0].message;
  EXPECT_TRUE(contains(events[0].message, "$.lighting.phase.forward")) << events[0].message;
  EXPECT_EQ(doc.state("fair_cumulus"), good);
  EXPECT_TRUE(doc.take_changed().empty());
  EXPECT_TRUE(doc.poll_disk().empty());  // reported once per change
  test::external_write(at("fair_cumulus.json"), "{ not json");
  events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Malformed);
  EXPECT_EQ(doc.state("fair_cumulus"), good);
  // Fixed again: taken.
  j["lighting"]["phase"]["forward"] = 0.5;
  test::external_write(at("fair_cumulus.json"), weather_state_text(j));
  events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Reloaded);
  EXPECT_FLOAT_EQ(doc.state("fair_cumulus").lighting.phase_forward, 0.5f);
}

TEST_F(DiskFixture, FilesAddedAndRemovedByOthers) {
  WeatherDocument doc = open();
  fs::copy_file(at("storm.json"), at("storm_copy.json"));
  fs::remove(at("clear.json"));
  auto events = doc.poll_disk();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Added);
  EXPECT_EQ(events[0].id, "storm_copy");
  EXPECT_EQ(events[1].kind, Kind::Removed);
  EXPECT_EQ(events[1].id, "clear");
  EXPECT_TRUE(doc.has("storm_copy"));
  EXPECT_FALSE(doc.has("clear"));
  EXPECT_FALSE(doc.dirty());
  EXPECT_EQ(doc.take_changed(), (std::vector<std::string>{"clear", "storm_copy"}));
  // Deleting a state being edited is a conflict; taking the disk's side removes it.
  doc.set("storm", "haze", 0.2);
  fs::remove(at("storm.json"));
  events = doc.poll_disk();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Conflict);
  EXPECT_TRUE(doc.has("storm"));
  doc.resolve_conflict("storm", true);
  EXPECT_FALSE(doc.has("storm"));
  EXPECT_FALSE(doc.dirty());
}

}  // namespace
}  // namespace cumulo::editor
