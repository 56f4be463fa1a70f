#include "modules/clouds/gameplay/cloud_growth.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "modules/clouds/bake/grow/grow_spec.h"
#include "modules/clouds/gameplay/game_events.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds::gameplay {
namespace {

std::string event_name(const JsonView& v) {
  const std::string name = v.as<std::string>();
  if (name.size() > 128) v.fail("an event name of at most 128 characters");
  return name;
}

}  // namespace

void restart_cloud_growth(CloudGrowth& g) {
  g.running = g.ended = g.step_once = false;
  g.sim_seconds = 0.0;
  g.target_steps = 0;
  ++g.generation;
}

void request_cloud_growth_reset(ecs::World& world, CloudGrowth& g, double sim_time) {
  if (!g.reset_event.empty()) schedule_event(world, g.reset_event, sim_time);
  else restart_cloud_growth(g);
}

bool cloud_growth_can_step_once(const CloudGrowth& g) { return g.running && g.paused && !g.ended; }

const char* cloud_growth_state(const CloudGrowth& g) {
  return g.ended ? "ended" : !g.running ? "not started" : g.paused ? "paused" : "growing";
}

CloudGrowth cloud_growth_from_json(const JsonView& v) {
  if (!v.is_object()) v.fail("expected an object");
  for (const std::string& k : v.keys())
    if (k != "spec" && k != "event" && k != "states" && k != "reset_event" && k != "speed" && k != "voxel" &&
        k != "start_running")
      v[k].fail("unknown key \"" + k + "\" (expected spec, event, states, reset_event, speed, voxel, start_running)");
  CloudGrowth g;
  g.where = v.where();
  g.spec = v.get<std::string>("spec");
  if (g.spec.empty()) v["spec"].fail("expected the path of a grow spec");
  if (g.spec.size() > 4096) v["spec"].fail("a path of at most 4096 characters");
  if (v.has("event")) g.event = event_name(v["event"]);
  if (v.has("reset_event")) g.reset_event = event_name(v["reset_event"]);
  if (v.has("states")) {
    const JsonView states = v["states"];
    if (!states.is_array()) states.fail("expected an array of weather state names");
    for (const JsonView& s : states.elements()) g.states.push_back(event_name(s));
  }
  if (v.has("speed")) g.speed = v["speed"].as_float_in(0.01f, 10000.0f);
  if (v.has("voxel")) g.voxel = v["voxel"].as_float_in(1.0f, 1000.0f);
  g.start_running = v.get<bool>("start_running", false);
  if (g.event.empty() && g.states.empty() && !g.start_running)
    v.fail("nothing starts the growth: give an \"event\", \"states\" or \"start_running\": true");
  g.running = g.start_running;
  return g;
}

Json cloud_growth_to_json(const CloudGrowth& g) {
  Json j = {{"spec", g.spec}, {"speed", g.speed}, {"voxel", g.voxel}};
  if (!g.event.empty()) j["event"] = g.event;
  if (!g.states.empty()) j["states"] = g.states;
  if (!g.reset_event.empty()) j["reset_event"] = g.reset_event;
  if (g.start_running) j["start_running"] = true;
  return j;
}

void register_cloud_growth_component(ecs::ComponentRegistry& registry) {
  registry.register_component<CloudGrowth>("CloudGrowth", cloud_growth_to_json, cloud_growth_from_json);
}

void resolve_cloud_growth(CloudGrowth& g, const std::filesystem::path& level_dir) {
  const std::filesystem::path path = std::filesystem::path(g.spec).is_absolute() ? std::filesystem::path(g.spec)
                                                                                 : level_dir / g.spec;
  grow::GrowSpec spec;
  try {
    spec = grow::load_grow_spec(path);
  } catch (const Error& e) {
    fail("%s: $.spec: %s", g.where.c_str(), e.what());
  }
  g.resolved_spec = path;
  g.last_step = spec.steps;
  g.step_seconds = spec.solver.dt;
}

double growth_steps_per_second(const CloudGrowth& g) {
  return g.step_seconds > 0.0f ? double(g.speed) / double(g.step_seconds) : 0.0;
}

void add_cloud_growth_system(ecs::Scheduler& s) {
  s.add_system(ecs::Phase::Update, "cloud growth",
               [reader = ecs::EventReader<GameEvent>{}](ecs::World& w, const ecs::FrameContext& f) mutable {
                 std::vector<std::string> fired;
                 for (const GameEvent& e : w.read(reader)) fired.push_back(e.name);
                 std::vector<std::string> weather;
                 w.view<const weather::WeatherScheduler>().each(
                     [&](const weather::WeatherScheduler& sch) { weather.push_back(sch.current); });
                 w.view<CloudGrowth>().each([&](CloudGrowth& g) {
                   for (const std::string& name : fired) {
                     if (!g.reset_event.empty() && name == g.reset_event) restart_cloud_growth(g);
                     if (!g.event.empty() && name == g.event && !g.running) g.running = true;
                   }
                   for (const std::string& state : weather)
                     if (!g.running && !g.ended && std::find(g.states.begin(), g.states.end(), state) != g.states.end())
                       g.running = true;
                   if (!g.running || g.ended || g.step_seconds <= 0.0f) return;
                   if (g.paused) {
                     if (!g.step_once) return;
                     g.step_once = false;
                     ++g.target_steps;
                     g.sim_seconds = double(g.target_steps) * g.step_seconds;
                   } else {
                     g.sim_seconds += f.dt * double(g.speed);
                     g.target_steps = int(std::floor(g.sim_seconds / double(g.step_seconds) + 1e-9));
                   }
                   if (g.last_step > 0 && g.target_steps >= g.last_step) {
                     g.target_steps = g.last_step;
                     g.ended = true;
                   }
                 });
               });
}

}  // namespace cumulo::clouds::gameplay
