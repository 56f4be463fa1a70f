#pragma once
// The weather's systems (Update phase): the WeatherSchedulers advance, each by the hour of the time of
// day that counts (scene::find_sun), the run's seed and the viewer's WeatherZone.
#include "engine/ecs/scheduler.h"

namespace cumulo::clouds::weather {

void add_weather_scheduler_system(ecs::Scheduler& s);

}  // namespace cumulo::clouds::weather
