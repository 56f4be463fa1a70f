// `cumulo run` with the clouds module, headless on lavapipe with validation: the cloud passes draw the
// level's Cloudscape over the scene, `--clouds off` gives exactly the frame of a level without one, a
// moved Transform moves the cloud, and the module's flags and level errors are refused clearly.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>


#include "engine/app/application.h"
#include "engine/app/recording.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "modules/clouds/clouds_module.h"
#include "modules/clouds/volume/import.h"
#include "modules/clouds/volume/import_outputs.h"
#include "tests/support/png_read.h"
#include "tests/support/temp_dir.h"
#include "tests/modules/clouds/module/clouds_run_fixture.h"

namespace fs = std::filesystem;
using namespace cumulo;

namespace {

using test::CloudsRun;
using test::Png;
using test::load_png;

const std::string kCloudEntity =
    R"({"name": "cloud", "components": {"Transform": {"position": [0, 500, 0]}, "Cloudscape": {"asset": "small_cloud.json"}}},)";

}  // namespace

TEST_F(CloudsRun, CloudsDrawAndOffGivesTheFrameWithoutThem) {
  fs::path with = level("with");
  fs::path without = level("without", kCloudEntity, "");
  ASSERT_EQ(run(with, "on.png"), 0);  // 3: validation errors
  ASSERT_EQ(run(with, "off.png", {"--clouds", "off"}), 0);
  ASSERT_EQ(run(without, "none.png"), 0);
  Png on = load_png(dir_ / "on.png"), off = load_png(dir_ / "off.png"), none = load_png(dir_ / "none.png");
  ASSERT_EQ(on.w, 160);
  EXPECT_EQ(off.rgba, none.rgba);  // bit-exact: the module added nothing
  // The cloud fills the middle of the view: the centre changes, the corners stay sky.
  double centre = 0;
  for (int y = 35; y < 55; ++y)
    for (int x = 70; x < 90; ++x)
      for (int c = 0; c < 3; ++c) centre += std::abs(on.at(x, y, c) - none.at(x, y, c));
  EXPECT_GT(centre / (20.0 * 20 * 3), 10.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(on.at(1, 1, c), none.at(1, 1, c), 3) << c;
  // The graph: the march and the composite between sky and tonemap; none of it with --clouds off.
  std::string g_on = read_file_text(dir_ / "on.png.txt"), g_off = read_file_text(dir_ / "off.png.txt");
  EXPECT_NE(g_on.find("clouds.march"), std::string::npos);
  EXPECT_LT(g_on.find(" sky ("), g_on.find("clouds.composite"));
  EXPECT_LT(g_on.find("clouds.composite"), g_on.find(" tonemap ("));
  EXPECT_EQ(g_off.find("clouds."), std::string::npos);
}

TEST_F(CloudsRun, MovedTransformMovesTheCloud) {
  fs::path centre = level("centre");
  fs::path right = level("right", "\"position\": [0, 500, 0]", "\"position\": [120, 500, 0]");
  fs::path without = level("without", kCloudEntity, "");
  ASSERT_EQ(run(centre, "centre.png"), 0);
  ASSERT_EQ(run(right, "right.png"), 0);
  ASSERT_EQ(run(without, "none.png"), 0);
  Png c = load_png(dir_ / "centre.png"), r = load_png(dir_ / "right.png"), n = load_png(dir_ / "none.png");
  double xc = diff_centroid_x(c, n), xr = diff_centroid_x(r, n);
  EXPECT_NEAR(xc, 80.0, 8.0);  // centred
  EXPECT_GT(xr, xc + 10.0);    // 120 m to the right at 450 m distance: about 20 px at 160 px / 60 deg
  EXPECT_GT(mean_diff(r, c), 0.3);  // identical frames would give 0
}

// A volume that did not come from our baker (an imported SDF: what `cumulo import` makes of a VDB or of
// TGA slices) renders like a baked one: same place, comparable coverage.
TEST_F(CloudsRun, ImportedVolumeRendersLikeABakedOne) {
  const glm::uvec3 dims(64, 32, 64);
  std::vector<float> sdf(size_t(dims.x) * dims.y * dims.z);
  for (uint32_t k = 0; k < dims.z; ++k)
    for (uint32_t j = 0; j < dims.y; ++j)
      for (uint32_t i = 0; i < dims.x; ++i) {
        glm::vec3 p = glm::vec3(-256.0f, 0.0f, -256.0f) + (glm::vec3(i, j, k) + 0.5f) * 8.0f;
        sdf[(size_t(k) * dims.y + j) * dims.x + i] = glm::length(p - glm::vec3(0, 128, 0)) - 100.0f;
      }
  clouds::DeriveOptions derive;
  derive.detail_type = 0.8f;
  clouds::write_imported_cloudscape(dir_ / "imported",
                                    clouds::nvdfs_from_sdf(sdf, dims, 8.0f, glm::vec3(-256.0f, 0.0f, -256.0f), derive));
  fs::path imported = level("imported", "\"asset\": \"small_cloud.json\"", "\"asset\": \"imported\"");
  fs::path baked = level("baked");
  fs::path without = level("without", kCloudEntity, "");
  ASSERT_EQ(run(imported, "imported.png"), 0);
  ASSERT_EQ(run(baked, "baked.png"), 0);
  ASSERT_EQ(run(without, "none.png"), 0);
  Png i = load_png(dir_ / "imported.png"), b = load_png(dir_ / "baked.png"), n = load_png(dir_ / "none.png");
  EXPECT_NEAR(diff_centroid_x(i, n), diff_centroid_x(b, n), 6.0);
  const double di = mean_diff(i, n), db = mean_diff(b, n);
  EXPECT_GT(di, 0.5 * db);  // the same sphere, without the recipe's erosion: similar coverage
  EXPECT_LT(di, 2.0 * db);
}

// A grown cloud (issue 20): a recipe that places the committed humilis of the sample level (its spec and
// grown folder copied beside the recipe, so nothing is grown) bakes and renders without validation errors,
// where it is placed, as cloud of its own simulated attributes.
TEST_F(CloudsRun, AGrownCloudRendersWhereItIsPlaced) {
  const fs::path grown = "content/levels/sample/grown";
  fs::copy_file(grown / "humilis.json", dir_ / "humilis.json");
  fs::copy(grown / "humilis", dir_ / "humilis", fs::copy_options::recursive);
  write_file_atomic(dir_ / "grown_cloud.json", R"({"name": "grown_test", "seed": 3, "voxel_size": 8,
    "bounds": {"min": [-256, 0, -256], "max": [256, 256, 256]},
    "edits": [{"type": "grown", "spec": "humilis.json", "position": [0, 60, 0]}]})");
  // The camera looks up at the cloud, so it stands against the sky rather than the bright horizon.
  auto grown_level = [&](const std::string& name, const std::string& position) {
    fs::path file = level(name, "\"asset\": \"small_cloud.json\"", "\"asset\": \"grown_cloud.json\"");
    std::string text = read_file_text(file);
    auto replace = [&](const std::string& from, const std::string& to) {
      const size_t p = text.find(from);
      EXPECT_NE(p, std::string::npos) << from;
      if (p != std::string::npos) text.replace(p, from.size(), to);
    };
    replace("\"position\": [0, 500, 0]", "\"position\": " + position);
    replace("\"look_at\": [0, 628, 0]", "\"look_at\": [0, 700, 0]");
    replace("\"position\": [0, 628, 450]", "\"position\": [0, 520, 450]");
    write_file_atomic(file, text);
    return file;
  };
  fs::path with = grown_level("grown", "[0, 500, 0]");
  fs::path right = grown_level("grown_right", "[100, 500, 0]");
  fs::path without = grown_level("without_grown", "[0, 500, 0]");
  {
    std::string text = read_file_text(without);
    const std::string entity = "{\"name\": \"cloud\", \"components\": {\"Transform\": {\"position\": [0, 500, 0]}, \"Cloudscape\": {\"asset\": \"grown_cloud.json\"}}},";
    const size_t p = text.find(entity);
    ASSERT_NE(p, std::string::npos);
    text.erase(p, entity.size());
    write_file_atomic(without, text);
  }
  ASSERT_EQ(run(with, "grown.png"), 0);  // 3: validation errors
  ASSERT_EQ(run(right, "grown_right.png"), 0);
  ASSERT_EQ(run(without, "none.png"), 0);
  Png g = load_png(dir_ / "grown.png"), r = load_png(dir_ / "grown_right.png"), n = load_png(dir_ / "none.png");
  int cloud_px = 0;
  for (int y = 0; y < g.h; ++y)
    for (int x = 0; x < g.w; ++x)
      cloud_px += std::abs(g.at(x, y, 0) - n.at(x, y, 0)) + std::abs(g.at(x, y, 1) - n.at(x, y, 1)) +
                      std::abs(g.at(x, y, 2) - n.at(x, y, 2)) > 24;
  EXPECT_GT(cloud_px, 300) << "the grown cloud (about 310 x 130 m at 450 m) covers part of the 160x90 view";
  EXPECT_LT(cloud_px, 160 * 90 / 3);
  EXPECT_NEAR(diff_centroid_x(g, n), 80.0, 12.0);
  EXPECT_GT(diff_centroid_x(r, n), diff_centroid_x(g, n) + 8.0) << "placed 100 m to the right";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(g.at(1, 1, c), n.at(1, 1, c), 3) << "the corners stay sky";
}

TEST_F(CloudsRun, DebugViewsRunClean) {
  fs::path with = level("with");
  for (const char* view : {"profile", "steps", "light-grid", "split"})
    EXPECT_EQ(run(with, std::string(view) + ".png", {"--cloud-debug", view, "--mode", "60"}, 1), 0) << view;
}

TEST_F(CloudsRun, BadFlagsAndLevelsAreRefusedClearly) {
  fs::path with = level("with");
  auto error_of = [&](const fs::path& file, std::vector<std::string> extra) -> std::string {
    try {
      run(file, "x.png", extra);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_NE(error_of(with, {"--cloud-debug", "heat"}).find("--cloud-debug"), std::string::npos);
  EXPECT_NE(error_of(with, {"--clouds", "maybe"}).find("--clouds"), std::string::npos);
  EXPECT_NE(error_of(with, {"--cloud-formats", "bc6h"}).find("--cloud-formats"), std::string::npos);
  EXPECT_NE(error_of(with, {"--cloud-ablation", "fast"}).find("--cloud-ablation"), std::string::npos);
  fs::path scaled = level("scaled", "\"position\": [0, 500, 0]", "\"position\": [0, 500, 0], \"scale\": [1, 2, 1]");
  std::string s = error_of(scaled, {});
  EXPECT_NE(s.find("uniform scale"), std::string::npos) << s;
  EXPECT_NE(s.find("Cloudscape"), std::string::npos) << s;
  fs::path missing = level("missing", "\"asset\": \"small_cloud.json\"", "\"asset\": \"absent.json\"");
  std::string m = error_of(missing, {});
  EXPECT_NE(m.find("missing.json"), std::string::npos) << m;
  EXPECT_NE(m.find("absent.json"), std::string::npos) << m;
  // Only a cloud grown during play (a CloudGrowth on the entity) may leave the asset out.
  fs::path no_asset = level("no_asset", "\"asset\": \"small_cloud.json\"", "\"density\": 1");
  std::string n = error_of(no_asset, {});
  EXPECT_NE(n.find("no_asset.json: $.entities"), std::string::npos) << n;
  EXPECT_NE(n.find("Cloudscape"), std::string::npos) << n;
  EXPECT_NE(n.find("\"asset\""), std::string::npos) << n;
  EXPECT_NE(n.find("CloudGrowth"), std::string::npos) << n;
}

namespace {

// `--weather ID` starts the run in a shipped weather state (content/weather/): its voxel density,
// lighting and wind reach the cloud passes; an unknown id is refused with the known ones.
TEST_F(CloudsRun, WeatherStateReachesTheCloudsAndUnknownIdsAreRefused) {
  fs::path with = level("with");
  ASSERT_EQ(run(with, "clear.png", {"--weather", "clear"}), 0);
  ASSERT_EQ(run(with, "storm.png", {"--weather", "storm"}), 0);
  ASSERT_EQ(run(with, "none.png"), 0);
  const Png clear = load_png(dir_ / "clear.png"), storm = load_png(dir_ / "storm.png"), none = load_png(dir_ / "none.png");
  const double d = mean_diff(clear, storm);
  std::printf("  mean |clear - storm| %.2f per channel, |none - storm| %.2f\n", d, mean_diff(none, storm));
  EXPECT_GT(d, 0.5);
  EXPECT_GT(mean_diff(none, storm), 0.2);
  try {
    run(with, "x.png", {"--weather", "drizzle"});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("drizzle"), std::string::npos) << m;
    EXPECT_NE(m.find("fair_cumulus"), std::string::npos) << m;
  }
}

}  // namespace

namespace {

// The Stormbird: `--event stormbird_killed@0` dissipates the cloud of the entity with the component
// (wisps first, over duration_s): after it the frame is the frame without clouds; without the event
// the cloud is still there.
TEST_F(CloudsRun, StormbirdKilledEventDissipatesTheCloud) {
  fs::path storm = level("storm", "\"Cloudscape\": {\"asset\": \"small_cloud.json\"}",
                         "\"Cloudscape\": {\"asset\": \"small_cloud.json\"}, \"StormbirdDissipation\": {\"duration_s\": 1}");
  fs::path with = level("with");
  ASSERT_EQ(run(storm, "alive.png", {"--start-at", "2"}), 0);
  ASSERT_EQ(run(storm, "dead.png", {"--event", "stormbird_killed@0.5", "--start-at", "2"}), 0);
  ASSERT_EQ(run(with, "off.png", {"--clouds", "off", "--start-at", "2"}), 0);
  const Png alive = load_png(dir_ / "alive.png"), dead = load_png(dir_ / "dead.png"), off = load_png(dir_ / "off.png");
  std::printf("  |alive - off| %.3f, |dead - off| %.3f per channel\n", mean_diff(alive, off), mean_diff(dead, off));
  EXPECT_GT(mean_diff(alive, off), 0.3);
  EXPECT_EQ(dead.rgba, off.rgba);  // fully dissipated: no cloud at all
  try {
    run(storm, "x.png", {"--event", "stormbird_killed"});
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("NAME@SECONDS"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

// A LightningEvent in the level (a flash at the cloud's centre, live on the first frames) reaches the
// renderer's point lights: the cloud glows where it is thin.
TEST_F(CloudsRun, ALightningFlashLightsTheCloud) {
  fs::path dark = level("dark");
  fs::path flash = level("flash", "{\"name\": \"cam\"",
                         "{\"name\": \"bolt\", \"components\": {\"LightningEvent\": {\"position\": [0, 628, 0], \"radius\": 300, "
                         "\"intensity\": 80, \"duration_s\": 5}}},\n    {\"name\": \"cam\"");
  ASSERT_EQ(run(dark, "dark.png", {"--time-of-day", "23"}, 2), 0);
  ASSERT_EQ(run(flash, "flash.png", {"--time-of-day", "23"}, 2), 0);
  const Png a = load_png(dir_ / "dark.png"), b = load_png(dir_ / "flash.png");
  double sa = 0, sb = 0;
  for (size_t i = 0; i < a.rgba.size(); i += 4) sa += a.rgba[i + 2], sb += b.rgba[i + 2];
  std::printf("  mean blue at night: %.2f dark, %.2f with the flash\n", sa / (a.rgba.size() / 4), sb / (b.rgba.size() / 4));
  EXPECT_GT(sb, sa * 1.02);
}

}  // namespace

namespace {

// `--record` writes the run's inputs; `--replay` of that file runs the same simulation: the same frame,
// and recording the replay gives the same file. A replay does not take --event; bad recordings are
// refused naming the file and the JSON path.
TEST_F(CloudsRun, RecordThenReplayGivesTheSameRunAndBadRecordingsAreNamed) {
  fs::path storm = level("storm", "\"Cloudscape\": {\"asset\": \"small_cloud.json\"}",
                         "\"Cloudscape\": {\"asset\": \"small_cloud.json\"}, \"StormbirdDissipation\": {\"duration_s\": 1}");
  const std::string a = (dir_ / "a.json").string(), b = (dir_ / "b.json").string();
  ASSERT_EQ(run(storm, "recorded.png", {"--event", "stormbird_killed@0.3", "--seed", "5", "--record", a}, 20), 0);
  ASSERT_EQ(run(storm, "replayed.png", {"--replay", a, "--record", b}, 20), 0);
  const app::Recording ra = app::load_recording(a), rb = app::load_recording(b);
  EXPECT_EQ(ra.seed, 5u);
  EXPECT_EQ(ra.steps, 40u);  // 20 frames at 30 Hz, 60 Hz steps
  ASSERT_EQ(ra.events.size(), 1u);
  EXPECT_EQ(ra.events[0].step, 18u);  // the step whose end passes 0.3 s: [18/60, 19/60)
  EXPECT_EQ(app::recording_to_json(ra), app::recording_to_json(rb));
  EXPECT_EQ(load_png(dir_ / "recorded.png").rgba, load_png(dir_ / "replayed.png").rgba);
  // Without --frames a headless replay lasts as long as the recording.
  ASSERT_EQ(run(storm, "again.png", {"--replay", a, "--record", b}, -1), 0);
  EXPECT_EQ(app::load_recording(b).steps, 40u);

  auto refused = [&](const std::vector<std::string>& extra, const std::string& expect) {
    try {
      run(storm, "x.png", extra);
      ADD_FAILURE() << "accepted: " << expect;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused({"--replay", a, "--event", "x@1"}, "--event and --replay");
  refused({"--replay", (dir_ / "missing.json").string()}, "missing.json");
  std::string text = read_file_text(a);
  const size_t step = text.find("\"step\"", text.find("\"events\""));
  ASSERT_NE(step, std::string::npos);
  write_file_atomic(dir_ / "bad_step.json", text.replace(step, text.find_first_not_of("0123456789", step + 8) - step, "\"step\": -3"));
  refused({"--replay", (dir_ / "bad_step.json").string()}, "bad_step.json: $.events[0].step");
  text = read_file_text(a);
  write_file_atomic(dir_ / "bad_format.json", text.replace(text.find("cumulo-recording"), 16, "something-else"));
  refused({"--replay", (dir_ / "bad_format.json").string()}, "$.format");
  write_file_atomic(dir_ / "truncated.json", read_file_text(a).substr(0, 40));
  refused({"--replay", (dir_ / "truncated.json").string()}, "truncated.json");
}

}  // namespace

namespace {

// Mean of channel sums over the rows [y0, y1) and the brightest pixel there.
struct RowStats {
  double mean = 0;
  int max = 0;
};
RowStats row_stats(const Png& p, int y0, int y1) {
  RowStats r;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < p.w; ++x) {
      const int v = p.at(x, y, 0) + p.at(x, y, 1) + p.at(x, y, 2);
      r.mean += v;
      r.max = std::max(r.max, v);
    }
  r.mean /= double((y1 - y0) * p.w);
  return r;
}

// A ground discharge under the cloud at night: its channel shows as a thin bright line below the cloud
// (most columns of those rows unchanged), and it is gone once the flash ends.
TEST_F(CloudsRun, AGroundDischargeShowsABoltBelowTheCloud) {
  fs::path dark = level("dark");
  const std::string bolt = "{\"name\": \"bolt\", \"components\": {\"LightningEvent\": {\"kind\": \"ground\", \"position\": [0, 540, 0], "
                           "\"intensity\": 80, \"duration_s\": 2}}},\n    {\"name\": \"cam\"";
  fs::path strike = level("strike", "{\"name\": \"cam\"", bolt);
  ASSERT_EQ(run(dark, "dark.png", {"--time-of-day", "23"}, 2), 0);
  ASSERT_EQ(run(strike, "strike.png", {"--time-of-day", "23"}, 2), 0);
  ASSERT_EQ(run(strike, "after.png", {"--time-of-day", "23", "--start-at", "3"}, 2), 0);
  const Png a = load_png(dir_ / "dark.png"), b = load_png(dir_ / "strike.png"), c = load_png(dir_ / "after.png");
  // Below the cloud on screen: the lowest third of the frame (the cloud's base is at 500 m, the camera at 628 m).
  const int y0 = a.h * 2 / 3;
  int changed_columns = 0;
  for (int x = 0; x < a.w; ++x) {
    int d = 0;
    for (int y = y0; y < a.h; ++y)
      for (int ch = 0; ch < 3; ++ch) d = std::max(d, std::abs(b.at(x, y, ch) - a.at(x, y, ch)));
    changed_columns += d > 60;
  }
  std::printf("  below the cloud: brightest %d dark, %d with the bolt; %d of %d columns lit\n", row_stats(a, y0, a.h).max,
              row_stats(b, y0, a.h).max, changed_columns, a.w);
  EXPECT_GT(row_stats(b, y0, a.h).max, row_stats(a, y0, a.h).max + 300);
  EXPECT_GE(changed_columns, 1);
  EXPECT_LT(changed_columns, a.w / 4);  // a channel, not a sheet
  EXPECT_EQ(c.rgba, a.rgba);            // the flash has ended
}

// Rain under a precipitating cloud greys the view below it; a fully dissipated cloud has neither cloud
// nor rain (the frame without the module's passes).
TEST_F(CloudsRun, RainFallsUnderAPrecipitatingCloudAndStopsWithDissipation) {
  const std::string from = "\"Cloudscape\": {\"asset\": \"small_cloud.json\"}";
  fs::path dry = level("dry");
  fs::path wet = level("wet", from, "\"Cloudscape\": {\"asset\": \"small_cloud.json\", \"rain\": 1}");
  fs::path gone = level("gone", from, "\"Cloudscape\": {\"asset\": \"small_cloud.json\", \"rain\": 1, \"dissipation\": 1}");
  ASSERT_EQ(run(dry, "dry.png", {}, 2), 0);
  ASSERT_EQ(run(wet, "wet.png", {}, 2), 0);
  ASSERT_EQ(run(gone, "gone.png", {}, 2), 0);
  ASSERT_EQ(run(dry, "off.png", {"--clouds", "off"}, 2), 0);
  const Png a = load_png(dir_ / "dry.png"), b = load_png(dir_ / "wet.png"), g = load_png(dir_ / "gone.png"),
            off = load_png(dir_ / "off.png");
  const int y0 = a.h * 2 / 3;
  std::printf("  below the cloud: |wet - dry| %.2f per channel\n", mean_diff(a, b));
  double below = 0;
  for (int y = y0; y < a.h; ++y)
    for (int x = a.w / 3; x < 2 * a.w / 3; ++x)
      for (int ch = 0; ch < 3; ++ch) below += std::abs(b.at(x, y, ch) - a.at(x, y, ch));
  below /= double((a.h - y0) * (a.w / 3) * 3);
  EXPECT_GT(below, 0.25);  // the column under the cloud's centre (a grey curtain before a grey ground)
  for (int y = 0; y < a.h / 3; ++y)  // rays from above the cloud base that rise never meet the column
    for (int x = 0; x < a.w; ++x)
      for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(b.at(x, y, ch), a.at(x, y, ch)) << x << ", " << y;
  EXPECT_EQ(g.rgba, off.rgba);
}

}  // namespace

// A level with orographic clouds and no cloudscape (no terrain either: the envelope sits on the sea) draws them: the
// renderer composites the envelope alone, the voxel clouds standing in as empty.
TEST_F(CloudsRun, OrographicCloudsDrawInALevelWithoutACloudscape) {
  const fs::path file = dir_ / "envelope_only.json";
  write_file_atomic(file, R"({"version": 1, "name": "envelope-only", "entities": [
    {"name": "sun", "components": {"TimeOfDay": {"hours": 12}}},
    {"name": "cap", "components": {"OrographicClouds": {"extent": {"min": [-600, -600], "max": [600, 600]},
      "resolution": 64, "rules": [{"type": "cap", "center": [0, 0], "radius_m": 400, "base_m": 100, "top_m": 400}]}}},
    {"name": "cam", "components": {"Transform": {"position": [0, 250, 700], "look_at": [0, 250, 0]}, "Camera": {}}}]})");
  ASSERT_EQ(run(file, "on.png", {}, 8), 0);  // 3: validation errors
  ASSERT_EQ(run(file, "off.png", {"--envelope", "off"}, 8), 0);
  const Png on = load_png(dir_ / "on.png"), off = load_png(dir_ / "off.png");
  ASSERT_EQ(on.w, 160);
  double centre = 0;
  for (int y = 35; y < 55; ++y)
    for (int x = 70; x < 90; ++x)
      for (int c = 0; c < 3; ++c) centre += std::abs(on.at(x, y, c) - off.at(x, y, c));
  EXPECT_GT(centre / (20.0 * 20 * 3), 10.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(on.at(1, 1, c), off.at(1, 1, c), 3) << c;
  const std::string g = read_file_text(dir_ / "on.png.txt");
  // A second OrographicClouds component is refused, naming both (the renderer bakes one set of maps).
  const fs::path two = dir_ / "two_envelopes.json";
  std::string text = read_file_text(file);
  const std::string cap = text.substr(text.find(R"({"name": "cap")"), text.find(R"({"name": "cam")") - text.find(R"({"name": "cap")"));
  std::string cap2 = cap;
  cap2.replace(cap2.find(R"("cap")"), 5, R"("cap2")");
  text.insert(text.find(R"({"name": "cam")"), cap2);
  write_file_atomic(two, text);
  try {
    run(two, "two.png", {}, 1);
    ADD_FAILURE() << "two OrographicClouds components were taken";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("entities[2].components.OrographicClouds"), std::string::npos) << m;
    EXPECT_NE(m.find("entities[1].components.OrographicClouds"), std::string::npos) << m;
  }
  EXPECT_NE(g.find("clouds.envelope"), std::string::npos);
  EXPECT_NE(g.find("clouds.composite"), std::string::npos);
  EXPECT_EQ(g.find("clouds.march"), std::string::npos);
}

// Issue 26 end to end: a Cloudscape without an asset and a CloudGrowth on its entity. Held (nothing started it) the
// sky is clear where it stands; its event starts the growth, and a few seconds of play later the cloud is there.
TEST_F(CloudsRun, AGrowingCloudBuildsAfterItsEvent) {
  write_file_atomic(dir_ / "growth.json",
                    std::string(R"({"preset": "mediocris", "seed": 3, "grid": {"cells": [16, 12, 16], "cell": 24},
                                    "time": {"steps": 40, "dt": 30}, "atmosphere": {"humidity": [0.95, 0.9]}})"));
  const fs::path grows = level("grows", R"("Cloudscape": {"asset": "small_cloud.json"})",
                               R"("Cloudscape": {"density": 1}, "CloudGrowth": {"spec": "growth.json", "event": "grow_now", "speed": 300, "voxel": 24})");
  const std::vector<std::string> pace = {"--start-at", "4", "--cloud-growth-steps-per-frame", "16",
                                         "--cloud-growth-update-frames", "2"};
  std::vector<std::string> event = pace;
  event.insert(event.begin(), {"--event", "grow_now@0"});
  ASSERT_EQ(run(grows, "held.png", pace, 6), 0);
  ASSERT_EQ(run(grows, "grown.png", event, 6), 0);
  const Png held = load_png(dir_ / "held.png"), grown = load_png(dir_ / "grown.png");
  // 4 s of play at 300 / 30 = 10 steps a second: the target is the spec's last step (40), taken 16 steps a frame
  // (spread: a frame steps, the next two draw the images, the second of them the images themselves): by the 6th frame
  // the images show 32 steps.
  const double d = mean_diff(held, grown);
  std::printf("growing cloud: mean |grown - held| %.2f per channel\n", d);
  EXPECT_GT(d, 2.0) << "the grown cloud does not show";
  const std::string graph = read_file_text(dir_ / "grown.png.txt");
  EXPECT_NE(graph.find("clouds.grow"), std::string::npos);
}
