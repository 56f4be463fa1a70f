#pragma once
// The level's weather as a world resource (LevelWeather), set when the level loads: the states of its
// weather folder, the state `--weather` names and the editor's preview. Systems (weather_systems.h,
// gameplay's lightning) and the extraction (frame/cloud_extraction.h) read it from the world; the editor
// edits it there.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/ecs/world.h"
#include "modules/clouds/weather/weather_library.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo::clouds::weather {

struct LevelWeather {
  // Loaded when the level has a WeatherScheduler or WeatherZone, names a state elsewhere or --weather is given.
  std::optional<WeatherLibrary> library;
  std::optional<WeatherState> start;    // --weather: the state schedulers start in, drawn when there is none
  std::optional<WeatherState> preview;  // the editor's: drawn instead of the scheduler's (the simulation goes on)
};

// A state that data outside weather/ names (a trigger's set_weather), with where it is named for the error.
struct NamedState {
  std::string state, where;
};

// "LEVEL: entity "NAME": COMPONENT", the place a level's component is named in errors.
std::string level_entity_where(const ecs::World& world, ecs::Entity e, const std::filesystem::path& level_file,
                               const char* component);

// Sets LevelWeather (a new one: no preview), its library from `folder` when the level has a WeatherScheduler
// or a WeatherZone, `named` is not empty or `start_id` is given: every state the level names checked
// against it (throws naming the level file, the entity and the state), the schedulers started in `start_id`,
// unnamed zones named after their entity.
void load_level_weather(ecs::World& world, const std::filesystem::path& level_file, const std::filesystem::path& folder,
                        const std::string& start_id, const std::vector<NamedState>& named);

// The weather drawn this frame: the preview, else the first scheduler's blend, else the --weather state.
std::optional<WeatherState> weather_drawn(const ecs::World& world);

}  // namespace cumulo::clouds::weather
