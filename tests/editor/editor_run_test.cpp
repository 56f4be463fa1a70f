// `cumulo edit --script` end to end: the real executable in a real window under Xvfb on lavapipe, with
// validation on (a validation error fails the run with exit code 3). The editor edits a copy of the
// shipped weather states (--weather-dir), so the repository's files are never touched.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "editor/model/weather_document.h"
#include "engine/core/file_io.h"
#include "engine/core/png.h"
#include "modules/clouds/weather/weather_state.h"
#include "tests/editor/editor_test_support.h"
#include "tests/engine/app/cli_test_util.h"
#include "tests/support/png_read.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using cumulo::test::CliResult;
using cumulo::test::run_cumulo;

namespace {

const std::string kLevel = "content/levels/sample/level.json";

// `cumulo edit` with no display needed (it fails before any window opens).
CliResult run_edit(const std::string& args) { return run_cumulo("edit " + args, "CUMULO_VALIDATION=1"); }

// `cumulo edit` in a window of an Xvfb display; `on_line` sees each line of its output as it comes (a test
// playing another program reacts to it). xvfb-run -a races other servers started at the same moment: a
// start that could not open its display is retried.
CliResult run_edit_in_xvfb(const std::string& args, const std::string& env = "",
                           const std::function<void(const std::string&)>& on_line = {}) {
  CliResult r;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const std::string cmd = "xvfb-run -a -s '-screen 0 800x600x24' env CUMULO_VALIDATION=1 " + env + " " +
                            std::string(CUMULO_EXE) + " edit " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    r.output.clear();
    char line[4096];
    while (fgets(line, sizeof line, p)) {
      r.output += line;
      if (on_line) on_line(line);
    }
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    if (r.output.find("Failed to open display") == std::string::npos &&
        r.output.find("cannot open display") == std::string::npos)
      return r;
    sleep(unsigned(2 * (attempt + 1)));
  }
  return r;
}

fs::path write_script(const fs::path& dir, const std::string& name, const std::string& json) {
  const fs::path p = dir / name;
  std::ofstream(p) << json;
  return p;
}

// The share of the viewport's upper half (between the editor's side panels: x 26-74 %, y 3-45 %) where
// the sky is blue rather than cloud: blue above red by 40 levels.
double blue_sky_share(const cumulo::test::Png& img) {
  int blue = 0, n = 0;
  for (int y = img.h * 3 / 100; y < img.h * 45 / 100; ++y)
    for (int x = img.w * 26 / 100; x < img.w * 74 / 100; ++x, ++n)
      if (img.at(x, y, 2) > img.at(x, y, 0) + 40) ++blue;
  return n ? double(blue) / n : 0.0;
}

class EditorRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed";
    dir_ = cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_edit"));
    weather_ = dir_ / "weather";
    fs::create_directories(weather_);
    cumulo::editor::test::copy_shipped_weather(weather_);
  }
  std::string args(const fs::path& script, const std::string& camera = "ground") const {
    return kLevel + " --weather-dir " + weather_.string() + " --size 480x270 --camera " + camera + " --script " +
           script.string();
  }
  fs::path dir_, weather_;
};

TEST_F(EditorRun, AScriptEditsPaintsAHoleUndoesRedoesSavesAndTheSavedFileReloadsToTheSameState) {
  const std::string original = cumulo::read_file_text(weather_ / "overcast_stratus.json");
  const fs::path shots = dir_ / "shots";
  // Four dabs half the map wide clear an overcast deck's whole map: the sky opens everywhere the 2.5D
  // layer draws. The wind is stilled so the map does not drift between the screenshots.
  std::string paint;
  for (const char* at : {"0.0, \"y\": 0.0", "0.5, \"y\": 0.0", "0.0, \"y\": 0.5", "0.5, \"y\": 0.5"})
    paint += std::string(R"({"do": "paint", "channel": "coverage", "x": )") + at + R"(, "radius": 0.45, "value": 0},)";
  const fs::path script = write_script(dir_, "edit.json", R"([
    {"do": "select_state", "name": "overcast_stratus"},
    {"do": "set", "param": "wind.speed", "value": 0},
    {"do": "set", "param": "lighting.absorption", "value": 0.07},
    {"do": "expect", "param": "lighting.absorption", "value": 0.07},
    {"do": "wait", "frames": 16},
    {"do": "screenshot", "path": ")" + (shots / "before.png").string() + R"("},
    )" + paint + R"(
    {"do": "wait", "frames": 1},
    {"do": "screenshot", "path": ")" + (shots / "next_frame.png").string() + R"("},
    {"do": "wait", "frames": 15},
    {"do": "screenshot", "path": ")" + (shots / "hole.png").string() + R"("},
    {"do": "undo"}, {"do": "undo"}, {"do": "undo"}, {"do": "undo"},
    {"do": "wait", "frames": 16},
    {"do": "screenshot", "path": ")" + (shots / "undone.png").string() + R"("},
    {"do": "redo"}, {"do": "redo"}, {"do": "redo"}, {"do": "redo"},
    {"do": "wait", "frames": 16},
    {"do": "screenshot", "path": ")" + (shots / "redone.png").string() + R"("},
    {"do": "expect_dirty", "value": true},
    {"do": "save"},
    {"do": "expect_dirty", "value": false},
    {"do": "quit"}])");
  const CliResult r = run_edit_in_xvfb(args(script));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("validation error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("editor CPU time per frame"), std::string::npos) << r.output;

  const double before = blue_sky_share(cumulo::test::load_png(shots / "before.png"));
  const double next_frame = blue_sky_share(cumulo::test::load_png(shots / "next_frame.png"));
  const double hole = blue_sky_share(cumulo::test::load_png(shots / "hole.png"));
  const double undone = blue_sky_share(cumulo::test::load_png(shots / "undone.png"));
  const double redone = blue_sky_share(cumulo::test::load_png(shots / "redone.png"));
  std::printf("blue sky share: before %.3f, the next frame %.3f, hole %.3f, undone %.3f, redone %.3f\n", before,
              next_frame, hole, undone, redone);
  EXPECT_GT(next_frame, before + 0.05) << "the edit shows in the viewport within a frame";
  EXPECT_GT(hole, before + 0.10) << "painting coverage 0 should open the overcast sky";
  EXPECT_NEAR(undone, before, 0.03) << "undoing the strokes should close it again";
  EXPECT_NEAR(redone, hole, 0.03) << "redoing them should open it again";

  // The saved state: the edits, the painted map beside it, the previous file kept as a backup.
  const auto saved = cumulo::clouds::weather::load_weather_state(weather_ / "overcast_stratus.json");
  EXPECT_EQ(saved.wind_speed, 0.0f);
  EXPECT_FLOAT_EQ(saved.lighting.absorption, 0.07f);
  ASSERT_EQ(saved.cloud_map.png, weather_ / "overcast_stratus.cloud_map.png");
  EXPECT_EQ(cumulo::read_file_text(weather_ / "overcast_stratus.json.bak"), original);
  const cumulo::ImageRgba8 map = cumulo::read_png_rgba8(saved.cloud_map.png);
  ASSERT_GT(map.width, 0u);
  EXPECT_EQ(map.rgba[0], 0) << "the painted hole's coverage at the map's corner";
  EXPECT_EQ(map.rgba[(size_t(map.height / 2) * map.width + map.width / 2) * 4], 0) << "and at its centre";

  // A second session loads the saved file: the same state, clean, drawing the same open sky.
  const fs::path reload = write_script(dir_, "reload.json", R"([
    {"do": "select_state", "name": "overcast_stratus"},
    {"do": "expect", "param": "wind.speed", "value": 0},
    {"do": "expect", "param": "lighting.absorption", "value": 0.07},
    {"do": "expect_dirty", "value": false},
    {"do": "wait", "frames": 16},
    {"do": "screenshot", "path": ")" + (shots / "reloaded.png").string() + R"("},
    {"do": "quit"}])");
  const CliResult r2 = run_edit_in_xvfb(args(reload));
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  const double reloaded = blue_sky_share(cumulo::test::load_png(shots / "reloaded.png"));
  std::printf("blue sky share after reloading the saved file: %.3f\n", reloaded);
  EXPECT_NEAR(reloaded, redone, 0.03);
}

TEST_F(EditorRun, ASaveIntoAReadOnlyFolderFailsWithAMessageAndLosesNothing) {
  const std::string original = cumulo::read_file_text(weather_ / "storm.json");
  // Root ignores permission bits: the folder is also made immutable where the file system allows it.
  fs::permissions(weather_, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const bool immutable = std::system(("chattr +i " + weather_.string() + " 2>/dev/null").c_str()) == 0;
  const bool writable = std::ofstream(weather_ / "probe").good();
  if (writable) {
    fs::remove(weather_ / "probe");
    fs::permissions(weather_, fs::perms::owner_all);
    GTEST_SKIP() << "cannot make a read-only folder here (root without chattr)";
  }
  const fs::path script = write_script(dir_, "readonly.json", R"([
    {"do": "select_state", "name": "storm"},
    {"do": "set", "param": "coverage", "value": 0.33},
    {"do": "save", "expect_failure": true},
    {"do": "expect", "param": "coverage", "value": 0.33},
    {"do": "expect_dirty", "value": true},
    {"do": "wait", "frames": 2},
    {"do": "quit", "discard": true}])");
  const CliResult r = run_edit_in_xvfb(args(script));
  if (immutable) std::system(("chattr -i " + weather_.string()).c_str());
  fs::permissions(weather_, fs::perms::owner_all);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("save failed as expected"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(weather_.string()), std::string::npos) << "the message names the file: " << r.output;
  EXPECT_EQ(cumulo::read_file_text(weather_ / "storm.json"), original);
  for (const auto& e : fs::directory_iterator(weather_)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  EXPECT_FALSE(fs::exists(weather_ / "storm.json.bak"));
}

TEST_F(EditorRun, AFailingScriptActionStopsTheScriptNamesItAndExitsNonZero) {
  const fs::path script = write_script(dir_, "bad.json", R"([
    {"do": "set", "param": "coverage", "value": 0.5},
    {"do": "select_state", "name": "no_such_state"},
    {"do": "save"}])");
  const CliResult r = run_edit_in_xvfb(args(script));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("bad.json: $[1]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no_such_state"), std::string::npos) << r.output;
  // The script stopped before its save: the edit of $[0] never reached the disk.
  EXPECT_FALSE(fs::exists(weather_ / "fair_cumulus.json.bak"));
}

// The growing storm (issue 26) as its panel drives it: paused and reset it holds step 0, started while paused it
// still does, each single step adds one, resumed it grows on its own, reset brings it back; a single step on a
// growth that is not running is refused, naming the action. Resumed, it waits 2 s and 8 frames: the play time a frame
// adds is at most 8 fixed steps (engine/app/fixed_step.h), so under a loaded CI 2 s alone gave it one step too few.
TEST_F(EditorRun, AScriptPausesStepsResumesAndResetsTheGrowingStorm) {
  const fs::path script = write_script(dir_, "growth.json", R"([
    {"do": "growth", "name": "storm_growth", "action": "pause"},
    {"do": "growth", "name": "storm_growth", "action": "reset"},
    {"do": "wait", "frames": 2},
    {"do": "expect_growth", "name": "storm_growth", "step": 0, "paused": true},
    {"do": "growth", "name": "storm_growth", "action": "start"},
    {"do": "wait", "frames": 3},
    {"do": "expect_growth", "name": "storm_growth", "step": 0},
    {"do": "growth", "name": "storm_growth", "action": "step"},
    {"do": "wait", "frames": 2},
    {"do": "expect_growth", "name": "storm_growth", "step": 1},
    {"do": "growth", "name": "storm_growth", "action": "step"},
    {"do": "wait", "frames": 2},
    {"do": "expect_growth", "name": "storm_growth", "step": 2, "paused": true},
    {"do": "growth", "name": "storm_growth", "action": "resume"},
    {"do": "wait", "seconds": 2},
    {"do": "wait", "frames": 8},
    {"do": "growth", "name": "storm_growth", "action": "pause"},
    {"do": "expect_growth", "name": "storm_growth", "min_step": 3, "paused": true},
    {"do": "growth", "name": "storm_growth", "action": "reset"},
    {"do": "wait", "frames": 2},
    {"do": "expect_growth", "name": "storm_growth", "step": 0},
    {"do": "growth", "name": "storm_growth", "action": "step"},
    {"do": "quit", "discard": true}])");
  const CliResult r = run_edit_in_xvfb(args(script, "squall"));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("growth.json: $[21]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("storm_growth steps one at a time only while running and paused (it is not started)"),
            std::string::npos)
      << r.output;
}

TEST_F(EditorRun, QuittingWithUnsavedChangesAsksFirst) {
  const fs::path script = write_script(dir_, "quit.json", R"([
    {"do": "set", "param": "coverage", "value": 0.5},
    {"do": "quit"}])");
  const CliResult r = run_edit_in_xvfb(args(script));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("unsaved changes"), std::string::npos) << r.output;
}

TEST_F(EditorRun, AStateChangedOnDiskIsReloadedAndAMalformedOneKeepsTheLastGoodState) {
  // Another program writes fair_cumulus.json twice while the editor runs: first a malformed version (the
  // editor must report it and keep the last good state), then, once the script has checked that, a valid
  // one (reloaded: the script sees its value). The script's screenshot is the signal between the two.
  const fs::path file = weather_ / "fair_cumulus.json";
  const std::string original = cumulo::read_file_text(file);
  const std::string key = "\"coverage\": 0.4,";
  const size_t at = original.find(key);
  ASSERT_NE(at, std::string::npos);
  const std::string malformed = std::string(original).replace(at, key.size(), "\"coverage\": \"lots\",");
  const std::string changed = std::string(original).replace(at, key.size(), "\"coverage\": 0.55,");
  const fs::path script = write_script(dir_, "watch.json", R"([
    {"do": "select_state", "name": "fair_cumulus"},
    {"do": "wait", "frames": 30},
    {"do": "expect", "param": "coverage", "value": 0.4},
    {"do": "screenshot", "path": ")" + (dir_ / "signal.png").string() + R"("},
    {"do": "wait", "frames": 40},
    {"do": "expect", "param": "coverage", "value": 0.55},
    {"do": "expect_dirty", "value": false},
    {"do": "quit"}])");
  bool wrote_malformed = false, wrote_changed = false;
  const CliResult r = run_edit_in_xvfb(
      kLevel + " --weather-dir " + weather_.string() + " --size 320x180 --camera ground --script " + script.string(), "",
      [&](const std::string& l) {
        if (!wrote_malformed && l.find("editor: editing") != std::string::npos) {
          cumulo::write_file_atomic(file, malformed);
          wrote_malformed = true;
        } else if (wrote_malformed && !wrote_changed && l.find("editor: wrote screenshot") != std::string::npos) {
          cumulo::write_file_atomic(file, changed);
          wrote_changed = true;
        }
      });
  const std::string& output = r.output;
  ASSERT_TRUE(wrote_malformed && wrote_changed) << output;
  EXPECT_EQ(r.exit_code, 0) << output;
  EXPECT_NE(output.find("fair_cumulus.json: $.coverage"), std::string::npos) << "the report names file and place: " << output;
  EXPECT_NE(output.find("the last good fair_cumulus keeps running"), std::string::npos) << output;
  EXPECT_NE(output.find("reloaded fair_cumulus"), std::string::npos) << output;
}

TEST_F(EditorRun, UndoAndRedoWalkOneHistoryOfWeatherAndWorldEdits) {
  // A weather edit, a cloudscape moved (a world edit), another weather edit: undo takes them back newest
  // first across both, redo brings them back oldest first.
  const fs::path script = write_script(dir_, "history.json", R"([
    {"do": "select_state", "name": "storm"},
    {"do": "set", "param": "coverage", "value": 0.3},
    {"do": "move_cloudscape", "name": "cloudscape", "position": [100, 0, -50]},
    {"do": "set", "param": "haze", "value": 0.5},
    {"do": "undo"},
    {"do": "expect", "param": "haze", "value": 0.4},
    {"do": "expect_cloudscape", "name": "cloudscape", "position": [100, 0, -50]},
    {"do": "undo"},
    {"do": "expect_cloudscape", "name": "cloudscape", "position": [0, 0, 0]},
    {"do": "expect", "param": "coverage", "value": 0.3},
    {"do": "undo"},
    {"do": "expect", "param": "coverage", "value": 0.75},
    {"do": "expect_dirty", "value": false},
    {"do": "redo"}, {"do": "redo"},
    {"do": "expect", "param": "coverage", "value": 0.3},
    {"do": "expect_cloudscape", "name": "cloudscape", "position": [100, 0, -50]},
    {"do": "redo"},
    {"do": "expect", "param": "haze", "value": 0.5},
    {"do": "wait", "frames": 2},
    {"do": "quit", "discard": true}])");
  const cumulo::clouds::weather::WeatherState storm = cumulo::clouds::weather::load_weather_state(weather_ / "storm.json");
  ASSERT_FLOAT_EQ(storm.coverage, 0.75f) << "the script expects the shipped storm's coverage";
  ASSERT_FLOAT_EQ(storm.haze, 0.4f) << "and its haze";
  const CliResult r = run_edit_in_xvfb(args(script));
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST_F(EditorRun, AShaderThatFailsToHotReloadIsShownAndTheOldPipelineKeepsRunning) {
  // A root of our own (CUMULO_ROOT): a copy of the shaders to break, the repository's content beside it.
  const fs::path root = dir_ / "root";
  fs::create_directories(root);
  fs::copy(cumulo::repo_root() / "shaders", root / "shaders", fs::copy_options::recursive);
  fs::create_directory_symlink(fs::absolute(cumulo::repo_root() / "content"), root / "content");
  const fs::path shader = root / "shaders" / "engine" / "tonemap.frag";
  const std::string good = cumulo::read_file_text(shader);
  const fs::path done = dir_ / "done";
  // The first screenshot says the pipelines are built (a shader that fails then is a hot reload's).
  const fs::path script = write_script(dir_, "shader.json", R"([
    {"do": "wait", "frames": 3},
    {"do": "screenshot", "path": ")" + (dir_ / "before.png").string() + R"("},
    {"do": "wait", "file": ")" + done.string() + R"(", "seconds": 300},
    {"do": "screenshot", "path": ")" + (dir_ / "after.png").string() + R"("},
    {"do": "quit"}])");
  int stage = 0;  // 0: running, 1: broken, 2: mended, 3: told the script
  const CliResult r = run_edit_in_xvfb(
      (cumulo::repo_root() / kLevel).string() + " --weather-dir " + weather_.string() +
          " --size 320x180 --camera ground --script " + script.string(),
      "CUMULO_ROOT=" + root.string(), [&](const std::string& l) {
        if (stage == 0 && l.find("editor: wrote screenshot") != std::string::npos) {
          cumulo::write_file_atomic(shader, good + "\nthis is not GLSL\n");
          stage = 1;
        } else if (stage == 1 && l.find("shader hot reload failed; the old pipeline keeps running") != std::string::npos) {
          cumulo::write_file_atomic(shader, good);
          stage = 2;
        } else if (stage == 2 && l.find("editor: shaders reloaded") != std::string::npos) {
          std::ofstream(done) << "mended";
          stage = 3;
        }
      });
  const std::string& output = r.output;
  EXPECT_EQ(stage, 3) << output;
  EXPECT_EQ(r.exit_code, 0) << output;
  EXPECT_NE(output.find("tonemap.frag"), std::string::npos) << "the error names the shader: " << output;
  EXPECT_EQ(output.find("validation error"), std::string::npos) << output;
  ASSERT_TRUE(fs::exists(dir_ / "after.png")) << "the run went on rendering after the failed reload";
  EXPECT_GT(cumulo::test::load_png(dir_ / "after.png").w, 0);
}

// These fail before any window opens.
// Issue 25: `cumulo edit` killed (SIGKILL) at every step of a save of two states (each state's file and its .bak copy
// written to temporaries, the journal, the four renames, the journal removed). Whatever the step, the folder the next
// session opens holds the whole old set or the whole new set, no temporary and no journal; and the next `cumulo edit`
// says in its log what it finished or removed.
TEST_F(EditorRun, AnEditorKilledAtAnyStepOfASaveLeavesTheOldSetOrTheNewOne) {
  const std::string clear0 = cumulo::read_file_text(weather_ / "clear.json");
  const std::string storm0 = cumulo::read_file_text(weather_ / "storm.json");
  const fs::path script = write_script(dir_, "save_two.json", R"([
    {"do": "select_state", "name": "clear"},
    {"do": "set", "param": "coverage", "value": 0.2},
    {"do": "select_state", "name": "storm"},
    {"do": "set", "param": "coverage", "value": 0.3},
    {"do": "save"},
    {"do": "quit"}])");
  const fs::path pristine = dir_ / "pristine";
  fs::copy(weather_, pristine, fs::copy_options::recursive);
  // A first session with nothing to save: whatever the level bakes on first use is in the cache before the steps
  // are counted (a bake's writes are file sets too).
  const fs::path quit = write_script(dir_, "quit.json", R"([{"do": "quit"}])");
  ASSERT_EQ(run_edit_in_xvfb(args(quit)).exit_code, 0);
  int killed = 0, mixed_on_disk = 0;
  for (int step = 1; step <= 12; ++step) {
    fs::remove_all(weather_);
    fs::copy(pristine, weather_, fs::copy_options::recursive);
    const CliResult r = run_edit_in_xvfb(args(script), "CUMULO_KILL_AT_SAVE_STEP=" + std::to_string(step));
    const bool completed = r.exit_code == 0;
    if (!completed) ++killed;
    // Straight after the kill the renames may be half done (the journal says how to finish them).
    const bool clear_new = cumulo::read_file_text(weather_ / "clear.json") != clear0;
    const bool storm_new = cumulo::read_file_text(weather_ / "storm.json") != storm0;
    if (clear_new != storm_new) ++mixed_on_disk;
    // The next session opens the folder: the same code `cumulo edit` opens it with.
    const std::vector<std::string> recovered = cumulo::recover_file_sets(weather_);
    const auto doc = cumulo::editor::WeatherDocument::open(weather_, cumulo::editor::test::fake_map);
    EXPECT_TRUE(doc.problems().empty()) << step;
    const float clear = cumulo::clouds::weather::load_weather_state(weather_ / "clear.json").coverage;
    const float storm = cumulo::clouds::weather::load_weather_state(weather_ / "storm.json").coverage;
    const bool all_new = clear == 0.2f && storm == 0.3f;
    const bool all_old = cumulo::read_file_text(weather_ / "clear.json") == clear0 &&
                         cumulo::read_file_text(weather_ / "storm.json") == storm0;
    EXPECT_TRUE(all_new || all_old) << "step " << step << ": clear " << clear << ", storm " << storm << "\n" << r.output;
    if (completed) EXPECT_TRUE(all_new) << step;
    for (const auto& e : fs::directory_iterator(weather_)) {
      EXPECT_NE(e.path().extension(), ".tmp") << "step " << step << ": " << e.path();
      EXPECT_NE(e.path().filename(), cumulo::kFileSetJournal) << "step " << step;
    }
    if (completed) break;  // past the last step
  }
  EXPECT_GE(killed, 10) << "a save of two states and their backups has at least ten steps";
  EXPECT_GT(mixed_on_disk, 0) << "no kill fell between two renames: the test would not see a journal at work";

  // The log of the next session: kill between the renames, then open the folder with `cumulo edit` itself.
  fs::remove_all(weather_);
  fs::copy(pristine, weather_, fs::copy_options::recursive);
  run_edit_in_xvfb(args(script), "CUMULO_KILL_AT_SAVE_STEP=6");
  ASSERT_TRUE(fs::exists(weather_ / cumulo::kFileSetJournal));
  const CliResult reopened = run_edit_in_xvfb(args(quit));
  ASSERT_EQ(reopened.exit_code, 0) << reopened.output;
  EXPECT_NE(reopened.output.find("finished an interrupted save"), std::string::npos) << reopened.output;
  EXPECT_FALSE(fs::exists(weather_ / cumulo::kFileSetJournal));
  EXPECT_FLOAT_EQ(cumulo::clouds::weather::load_weather_state(weather_ / "clear.json").coverage, 0.2f);
  EXPECT_FLOAT_EQ(cumulo::clouds::weather::load_weather_state(weather_ / "storm.json").coverage, 0.3f);
}

// A new user's game: content/ copied, the copied level edited and saved. The save lands in the copy's
// weather folder (the level's "folders": {"weather": "../../weather"}); the repository's states stay as shipped.
TEST_F(EditorRun, ACopiedLevelSavesIntoItsOwnWeatherFolder) {
  const fs::path game = dir_ / "game";
  fs::create_directories(game);
  fs::copy("content", game / "content", fs::copy_options::recursive);
  const std::string shipped = cumulo::read_file_text("content/weather/clear.json");
  const fs::path script = write_script(dir_, "copy.json", R"([
    {"do": "select_state", "name": "clear"},
    {"do": "set", "param": "coverage", "value": 0.2},
    {"do": "save"},
    {"do": "quit"}])");
  const CliResult r = run_edit_in_xvfb((game / "content/levels/sample/level.json").string() + " --size 320x180 --script " +
                                       script.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(cumulo::read_file_text("content/weather/clear.json"), shipped);
  const cumulo::clouds::weather::WeatherState saved =
      cumulo::clouds::weather::load_weather_state(game / "content/weather/clear.json");
  EXPECT_FLOAT_EQ(saved.coverage, 0.2f);
}

TEST(EditorCli, AnUnknownScriptActionIsRefusedBeforeTheEditorStarts) {
  const fs::path dir = cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_edit_cli"));
  const fs::path script = write_script(dir, "unknown.json", R"([{"do": "wait", "frames": 1}, {"do": "fly"}])");
  const CliResult r = run_edit(kLevel + " --script " + script.string());
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("unknown.json: $[1]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("select_state"), std::string::npos) << "lists the known actions: " << r.output;
}

TEST(EditorCli, TheEditorNeedsAWindow) {
  const CliResult headless = run_edit(kLevel + " --headless");
  EXPECT_NE(headless.exit_code, 0) << headless.output;
  EXPECT_NE(headless.output.find("needs a window"), std::string::npos) << headless.output;
  const CliResult no_display = run_cumulo("edit " + kLevel, "DISPLAY= WAYLAND_DISPLAY=");
  EXPECT_NE(no_display.exit_code, 0) << no_display.output;
  EXPECT_NE(no_display.output.find("xvfb-run"), std::string::npos) << no_display.output;
}

}  // namespace
