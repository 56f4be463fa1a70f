// A level owns its weather folder ("folders": {"weather": ...}, relative to the level file), --weather-dir
// overrides it, and the level's weather is a world resource (weather/level_weather.h) the systems and the
// extraction read: a copy of a level runs on its own copy of the states.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "engine/app/simulation.h"
#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/render/frame_snapshot.h"
#include "modules/clouds/clouds_module.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/weather/level_weather.h"
#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using namespace cumulo;
using namespace cumulo::clouds;

namespace {

// A level with one WeatherScheduler whose lightning volume is set, and `folders` as given ("" for none).
fs::path write_level(const fs::path& dir, const std::string& folders) {
  const fs::path file = dir / "level.json";
  write_file_atomic(file, std::string(R"({"version": 1, )") + (folders.empty() ? "" : "\"folders\": " + folders + ", ") +
                              R"("entities": [{"name": "weather", "components": {"WeatherScheduler": {"start": "storm",
                                 "schedule": [{"state": "storm", "weight": 1}],
                                 "lightning_volume": {"min": [0, 600, 0], "max": [100, 900, 100]}}}}]})");
  return file;
}

// A weather folder with the shipped storm, its lightning rate changed so the copy is told apart.
void write_weather(const fs::path& dir, float lightning_per_minute) {
  fs::create_directories(dir);
  Json storm = Json::parse(read_file_text(repo_root() / "content/weather/storm.json"));
  storm["lightning"]["frequency_per_minute"] = lightning_per_minute;
  write_file_atomic(dir / "storm.json", storm.dump(2));
}

struct WeatherRun {
  std::shared_ptr<CloudsModule> module = std::make_shared<CloudsModule>();
  std::unique_ptr<app::Simulation> sim;
  explicit WeatherRun(const fs::path& level, const std::string& weather_dir = "") {
    module->simulation_options().weather_dir = weather_dir;
    app::SimulationDesc d;
    d.level = level;
    d.modules = {module};
    sim = std::make_unique<app::Simulation>(d);
  }
  float lightning_per_minute() {
    sim->step(2);
    const auto* lw = sim->world().try_resource<gameplay::LightningWeather>();
    return lw ? lw->per_minute : -1.0f;
  }
};

}  // namespace

TEST(LevelWeather, ALevelReadsTheWeatherFolderItNames) {
  test::TempDir tmp("cumulo_level_weather");
  write_weather(tmp.path / "my_weather", 7.0f);
  WeatherRun run(write_level(tmp.path, R"({"weather": "my_weather"})"));
  EXPECT_EQ(run.module->weather_folder(), (tmp.path / "my_weather").lexically_normal());
  const auto* lw = run.sim->world().try_resource<weather::LevelWeather>();
  ASSERT_TRUE(lw && lw->library);
  EXPECT_EQ(lw->library->folder(), (tmp.path / "my_weather").lexically_normal());
  EXPECT_FLOAT_EQ(run.lightning_per_minute(), 7.0f);  // the copy's storm drives the lightning system
}

TEST(LevelWeather, WeatherDirOverridesTheLevelsAndNoFolderMeansTheRepositorys) {
  test::TempDir tmp("cumulo_level_weather_override");
  write_weather(tmp.path / "my_weather", 7.0f);
  write_weather(tmp.path / "other", 3.0f);
  WeatherRun over(write_level(tmp.path, R"({"weather": "my_weather"})"), (tmp.path / "other").string());
  EXPECT_FLOAT_EQ(over.lightning_per_minute(), 3.0f);
  const fs::path plain_dir = tmp.path / "plain";
  fs::create_directories(plain_dir);
  WeatherRun plain(write_level(plain_dir, ""));
  EXPECT_EQ(plain.module->weather_folder(), weather::WeatherLibrary::default_folder());
  const float shipped = Json::parse(read_file_text(repo_root() / "content/weather/storm.json"))["lightning"]["frequency_per_minute"];
  EXPECT_FLOAT_EQ(plain.lightning_per_minute(), shipped);
}

TEST(LevelWeather, AMissingOrMalformedFolderIsRefusedNamingTheLevel) {
  test::TempDir tmp("cumulo_level_weather_bad");
  const fs::path level = write_level(tmp.path, R"({"weather": "nowhere"})");
  try {
    WeatherRun run(level);
    FAIL() << "a missing weather folder was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(level.string()), std::string::npos) << m;
    EXPECT_NE(m.find("folders.weather"), std::string::npos) << m;
    EXPECT_NE(m.find("nowhere"), std::string::npos) << m;
  }
  try {
    WeatherRun run(write_level(tmp.path, R"({"weather": 3})"));
    FAIL() << "a number was accepted as a folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("folders.weather"), std::string::npos) << e.what();
  }
}

// The editor's preview (a world resource now) is what the extraction draws, over the scheduler's weather.
TEST(LevelWeather, ThePreviewInTheWorldIsTheWeatherDrawn) {
  test::TempDir tmp("cumulo_level_weather_preview");
  write_weather(tmp.path / "w", 7.0f);
  WeatherRun run(write_level(tmp.path, R"({"weather": "w"})"));
  auto& lw = run.sim->world().resource<weather::LevelWeather>();
  EXPECT_EQ(weather::weather_drawn(run.sim->world())->id, "storm");
  weather::WeatherState preview = lw.library->get("storm");
  preview.id = "preview";
  preview.coverage = 0.123f;
  lw.preview = preview;
  cumulo::render::FrameSnapshot snapshot;
  run.module->extract(run.sim->world(), snapshot);
  const CloudFrame& frame = snapshot.extensions.get<CloudFrame>();
  ASSERT_TRUE(frame.weather);
  EXPECT_EQ(frame.weather->id, "preview");
  EXPECT_FLOAT_EQ(frame.sky.coverage, 0.123f);
}
