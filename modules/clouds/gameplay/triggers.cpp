#include "modules/clouds/gameplay/triggers.h"

#include "engine/app/sim_resources.h"
#include "engine/core/error.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/gameplay/game_events.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds::gameplay {
namespace {

void only_keys(const JsonView& v, const std::vector<std::string>& allowed) {
  for (const std::string& k : v.keys())
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      v.fail("unknown key \"" + k + "\" (expected " + list + ")");
    }
}

TriggerVolume volume_from_json(const JsonView& v) {
  only_keys(v, {"box", "sphere"});
  if (v.has("box") == v.has("sphere")) v.fail("expected exactly one of \"box\" and \"sphere\"");
  TriggerVolume t;
  if (v.has("box")) {
    t.min = v["box"]["min"].as_vec3();
    t.max = v["box"]["max"].as_vec3();
    if (!glm::all(glm::lessThan(t.min, t.max))) v["box"].fail("expected min < max on every axis");
  } else {
    t.sphere = true;
    t.center = v["sphere"]["center"].as_vec3();
    t.radius = v["sphere"]["radius"].as_float_in(0.01f, 1e7f);
  }
  return t;
}

Json volume_to_json(const TriggerVolume& t) {
  if (t.sphere) return {{"sphere", {{"center", {t.center.x, t.center.y, t.center.z}}, {"radius", t.radius}}}};
  return {{"box", {{"min", {t.min.x, t.min.y, t.min.z}}, {"max", {t.max.x, t.max.y, t.max.z}}}}};
}

TriggerAction action_from_json(const JsonView& v) {
  static const std::vector<std::string> kinds = {"set_weather",      "encounter",       "fire_event",
                                                 "strike_lightning", "set_time_of_day", "move_cloudscape"};
  TriggerAction a{};
  a.kind = TriggerAction::Kind(v["do"].as_enum(kinds));
  switch (a.kind) {
    case TriggerAction::Kind::SetWeather:
      only_keys(v, {"do", "state"});
      a.text = v.get<std::string>("state");
      break;
    case TriggerAction::Kind::Encounter:
      only_keys(v, {"do", "active"});
      a.flag = v.get<bool>("active");
      break;
    case TriggerAction::Kind::FireEvent:
      only_keys(v, {"do", "name"});
      a.text = v.get<std::string>("name");
      if (a.text.empty()) v["name"].fail("expected an event name");
      break;
    case TriggerAction::Kind::StrikeLightning:
      only_keys(v, {"do", "position", "kind", "intensity", "radius"});
      a.position = v["position"].as_vec3();
      a.flag = v.has("kind") && v["kind"].as_name(kLightningKindNames) == LightningKind::Ground;  // true: a ground discharge
      a.number = v.has("intensity") ? v["intensity"].as_float_in(0.0f, 1e6f) : LightningEvent{}.intensity;
      a.radius = v.has("radius") ? v["radius"].as_float_in(1.0f, 1e5f) : LightningEvent{}.radius;
      break;
    case TriggerAction::Kind::SetTimeOfDay:
      only_keys(v, {"do", "hours"});
      a.number = v["hours"].as_float_in(0.0f, 24.0f);
      break;
    case TriggerAction::Kind::MoveCloudscape:
      only_keys(v, {"do", "entity", "position", "euler_deg", "scale"});
      a.text = v.get<std::string>("entity");
      if (v.has("position")) a.position = v["position"].as_vec3(), a.has_position = true;
      if (v.has("euler_deg")) a.euler_deg = v["euler_deg"].as_vec3();
      if (v.has("scale")) a.scale = v["scale"].as_float_in(1e-3f, 1e3f);
      break;
  }
  return a;
}

Json action_to_json(const TriggerAction& a) {
  switch (a.kind) {
    case TriggerAction::Kind::SetWeather: return {{"do", "set_weather"}, {"state", a.text}};
    case TriggerAction::Kind::Encounter: return {{"do", "encounter"}, {"active", a.flag}};
    case TriggerAction::Kind::FireEvent: return {{"do", "fire_event"}, {"name", a.text}};
    case TriggerAction::Kind::StrikeLightning:
      return {{"do", "strike_lightning"},
              {"position", {a.position.x, a.position.y, a.position.z}},
              {"kind", name_of(kLightningKindNames, a.flag ? LightningKind::Ground : LightningKind::Internal)},
              {"intensity", a.number},
              {"radius", a.radius}};
    case TriggerAction::Kind::SetTimeOfDay: return {{"do", "set_time_of_day"}, {"hours", a.number}};
    case TriggerAction::Kind::MoveCloudscape: {
      Json j = {{"do", "move_cloudscape"}, {"entity", a.text}};
      if (a.has_position) j["position"] = {a.position.x, a.position.y, a.position.z};
      if (a.euler_deg) j["euler_deg"] = {a.euler_deg->x, a.euler_deg->y, a.euler_deg->z};
      if (a.scale) j["scale"] = *a.scale;
      return j;
    }
  }
  return {};
}

void run_action(ecs::World& w, const TriggerAction& a) {
  switch (a.kind) {
    case TriggerAction::Kind::SetWeather:
      w.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& s) { weather::force_state(s, a.text); });
      break;
    case TriggerAction::Kind::Encounter:
      w.view<weather::WeatherScheduler>().each([&](weather::WeatherScheduler& s) { s.encounter_active = a.flag && !s.encounter.empty(); });
      break;
    case TriggerAction::Kind::FireEvent: fire_event(w, a.text); break;
    case TriggerAction::Kind::StrikeLightning:
      strike_lightning(w, a.position, a.flag ? LightningKind::Ground : LightningKind::Internal, a.number, a.radius);
      break;
    case TriggerAction::Kind::SetTimeOfDay: scene::time_of_day_to_set(w).hours = a.number; break;
    case TriggerAction::Kind::MoveCloudscape: {
      const ecs::Entity e = w.find(a.text);
      if (!w.valid(e) || !w.has<Cloudscape>(e))
        fail("trigger move_cloudscape: no entity \"%s\" with a Cloudscape", a.text.c_str());
      scene::Transform& t = w.has<scene::Transform>(e) ? w.get<scene::Transform>(e) : w.emplace<scene::Transform>(e);
      if (a.has_position) t.position = a.position;
      if (a.euler_deg) t.rotation = scene::euler_degrees_to_quat(*a.euler_deg);
      if (a.scale) t.scale = glm::vec3(*a.scale);
      break;
    }
  }
}

}  // namespace

bool TriggerVolume::contains(glm::vec3 p) const {
  if (sphere) return glm::distance(p, center) <= radius;
  return glm::all(glm::greaterThanEqual(p, min)) && glm::all(glm::lessThanEqual(p, max));
}

Trigger trigger_from_json(const JsonView& v) {
  only_keys(v, {"when", "once", "actions"});
  Trigger t;
  const JsonView when = v["when"];
  only_keys(when, {"enter", "exit", "event", "time"});
  if (when.keys().size() != 1) when.fail("expected exactly one of enter, exit, event, time");
  if (when.has("enter")) t.when = Trigger::When::Enter, t.volume = volume_from_json(when["enter"]);
  if (when.has("exit")) t.when = Trigger::When::Exit, t.volume = volume_from_json(when["exit"]);
  if (when.has("event")) t.when = Trigger::When::Event, t.event = when.get<std::string>("event");
  if (when.has("time")) t.when = Trigger::When::Time, t.time = when["time"].as_float_in(0.0f, 1e7f);
  t.once = v.get<bool>("once", true);
  for (const JsonView& a : v["actions"].elements()) t.actions.push_back(action_from_json(a));
  if (t.actions.empty()) v["actions"].fail("expected at least one action");
  return t;
}

Json trigger_to_json(const Trigger& t) {
  Json when;
  switch (t.when) {
    case Trigger::When::Enter: when = {{"enter", volume_to_json(t.volume)}}; break;
    case Trigger::When::Exit: when = {{"exit", volume_to_json(t.volume)}}; break;
    case Trigger::When::Event: when = {{"event", t.event}}; break;
    case Trigger::When::Time: when = {{"time", t.time}}; break;
  }
  Json actions = Json::array();
  for (const TriggerAction& a : t.actions) actions.push_back(action_to_json(a));
  return {{"when", when}, {"once", t.once}, {"actions", actions}};
}

void register_trigger_component(ecs::ComponentRegistry& registry) {
  registry.register_component<Trigger>("Trigger", trigger_to_json, trigger_from_json);
}

std::vector<std::string> trigger_weather_states(const Trigger& t) {
  std::vector<std::string> out;
  for (const TriggerAction& a : t.actions)
    if (a.kind == TriggerAction::Kind::SetWeather) out.push_back(a.text);
  return out;
}

std::vector<weather::NamedState> trigger_weather_references(const ecs::World& world, const std::filesystem::path& level_file) {
  std::vector<weather::NamedState> out;
  world.view<const Trigger>().each([&](ecs::Entity e, const Trigger& t) {
    for (const std::string& state : trigger_weather_states(t))
      out.push_back({state, weather::level_entity_where(world, e, level_file, "Trigger set_weather")});
  });
  return out;
}

void add_trigger_system(ecs::Scheduler& s) {
  s.add_system(ecs::Phase::Update, "triggers",
               [reader = ecs::EventReader<GameEvent>{}](ecs::World& w, const ecs::FrameContext& f) mutable {
                 std::vector<std::string> fired_events;
                 for (const GameEvent& e : w.read(reader)) fired_events.push_back(e.name);
                 std::optional<glm::vec3> viewer;
                 if (const auto* v = w.try_resource<app::Viewer>())
                   if (w.valid(v->entity) && w.has<scene::Transform>(v->entity)) viewer = w.get<scene::Transform>(v->entity).position;
                 std::vector<const Trigger*> due;
                 w.view<Trigger>().each([&](Trigger& t) {
                   if (t.once && t.fired) return;
                   bool fire = false;
                   switch (t.when) {
                     case Trigger::When::Enter:
                     case Trigger::When::Exit: {
                       const bool inside = viewer && t.volume.contains(*viewer);
                       // The first step only records where the viewer starts (starting inside is not "entering").
                       if (t.primed) fire = t.when == Trigger::When::Enter ? inside && !t.inside : !inside && t.inside;
                       t.inside = inside, t.primed = true;
                       break;
                     }
                     case Trigger::When::Event:
                       fire = std::find(fired_events.begin(), fired_events.end(), t.event) != fired_events.end();
                       break;
                     case Trigger::When::Time: fire = !t.fired && t.time < f.time + f.dt; break;
                   }
                   if (fire) t.fired = true, due.push_back(&t);
                 });
                 // Actions after the view: they may create entities (lightning) or fire events.
                 std::vector<TriggerAction> actions;
                 for (const Trigger* t : due) actions.insert(actions.end(), t->actions.begin(), t->actions.end());
                 for (const TriggerAction& a : actions) run_action(w, a);
               });
}

}  // namespace cumulo::clouds::gameplay
