#include "modules/clouds/weather/level_weather.h"

#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::clouds::weather {

std::string level_entity_where(const ecs::World& world, ecs::Entity e, const std::filesystem::path& level_file,
                               const char* component) {
  const auto* n = world.try_get<ecs::Name>(e);
  return level_file.string() + ": entity \"" + (n ? n->value : "?") + "\": " + component;
}

void load_level_weather(ecs::World& world, const std::filesystem::path& level_file, const std::filesystem::path& folder,
                        const std::string& start_id, const std::vector<NamedState>& named) {
  const ecs::World& cw = world;
  bool needed = !named.empty() || !start_id.empty();
  cw.view<const WeatherScheduler>().each([&](const WeatherScheduler&) { needed = true; });
  cw.view<const WeatherZone>().each([&](const WeatherZone&) { needed = true; });
  LevelWeather lw;
  if (!needed) {
    world.set_resource<LevelWeather>(std::move(lw));
    return;
  }
  const WeatherLibrary& library = lw.library.emplace(WeatherLibrary::load(folder));
  if (!start_id.empty()) lw.start = library.get(start_id);
  world.view<WeatherScheduler>().each([&](ecs::Entity e, WeatherScheduler& w) {
    if (lw.start) w.start = lw.start->id;
    check_scheduler_states(w, library, level_entity_where(world, e, level_file, "WeatherScheduler"));
  });
  world.view<WeatherZone>().each([&](ecs::Entity e, WeatherZone& z) {
    if (const auto* n = cw.try_get<ecs::Name>(e); z.name.empty() && n) z.name = n->value;
    for (const ScheduleEntry& s : z.states) library.require(s.state, level_entity_where(world, e, level_file, "WeatherZone"));
  });
  for (const NamedState& n : named) library.require(n.state, n.where);
  world.set_resource<LevelWeather>(std::move(lw));
}

std::optional<WeatherState> weather_drawn(const ecs::World& world) {
  const LevelWeather* lw = world.try_resource<LevelWeather>();
  if (!lw) return std::nullopt;
  if (lw->preview) return lw->preview;
  std::optional<WeatherState> state;
  if (lw->library)
    world.view<const WeatherScheduler>().each([&](const WeatherScheduler& w) {
      if (!state) state = weather_now(w, *lw->library).state;  // the first one counts
    });
  return state ? state : lw->start;
}

}  // namespace cumulo::clouds::weather
