#include "modules/clouds/gameplay/lightning.h"

#include <algorithm>
#include <cstring>
#include <cmath>

#include "engine/app/sim_resources.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "modules/clouds/weather/level_weather.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds::gameplay {

LightningEvent lightning_event_from_json(const JsonView& v) {
  for (const std::string& k : v.keys())
    if (k != "kind" && k != "position" && k != "radius" && k != "intensity" && k != "duration_s")
      v.fail("unknown key \"" + k + "\" (expected kind, position, radius, intensity, duration_s)");
  LightningEvent e;
  if (v.has("kind")) e.kind = v["kind"].as_name(kLightningKindNames);
  e.position = v["position"].as_vec3();
  if (v.has("radius")) e.radius = v["radius"].as_float_in(1.0f, 1e5f);
  if (v.has("intensity")) e.intensity = v["intensity"].as_float_in(0.0f, 1e6f);
  if (v.has("duration_s")) e.duration_s = v["duration_s"].as_float_in(0.01f, 60.0f);
  // The channel's shape from where the event sits in the level and where it strikes, never from the file's name: the
  // same level renders the same bolt from any folder (a test's temporary one included).
  e.seed = hash64(v.path().data(), v.path().size(), hash64(&e.position, sizeof e.position, uint64_t(e.kind)));
  return e;
}

Json lightning_event_to_json(const LightningEvent& e) {
  return {{"kind", name_of(kLightningKindNames, e.kind)},
          {"position", {e.position.x, e.position.y, e.position.z}},
          {"radius", e.radius},
          {"intensity", e.intensity},
          {"duration_s", e.duration_s}};
}

void register_lightning_component(ecs::ComponentRegistry& registry) {
  registry.register_component<LightningEvent>("LightningEvent", lightning_event_to_json, lightning_event_from_json);
}

float lightning_envelope(const LightningEvent& e) {
  const float t = e.age_s;
  if (t < 0.0f || t >= e.duration_s) return 0.0f;
  constexpr float kRise = 0.03f;
  if (t < kRise) return t / kRise;
  // Re-strokes: 3-5 pulses spread over the life, each a short bright peak over a decaying glow.
  SplitMix64 s{e.seed};
  const int strokes = 3 + int(s.uniform() * 3.0f);
  float flicker = 0.0f;
  for (int k = 0; k < strokes; ++k) {
    const float at = e.duration_s * (0.1f + 0.8f * s.uniform());
    const float d = (t - at) / 0.04f;
    flicker = std::max(flicker, std::exp(-d * d));
  }
  const float decay = std::exp(-3.0f * t / e.duration_s);
  return std::clamp(0.35f * decay + 0.65f * flicker * decay + (t < 0.1f ? 1.0f - t / 0.1f : 0.0f), 0.0f, 1.0f);
}

ecs::Entity strike_lightning(ecs::World& world, glm::vec3 position, LightningKind kind, float intensity, float radius) {
  LightningEvent e;
  e.kind = kind;
  e.position = position;
  e.intensity = intensity;
  e.radius = radius;
  const auto* seed = world.try_resource<app::SimulationSeed>();
  uint64_t p[4] = {};  // the position fills 12 of the first 16 bytes: the rest must not be the stack's leftovers
  std::memcpy(p, &position, sizeof position);
  p[3] = world.alive_count();
  e.seed = hash64(p, sizeof p, seed ? seed->value : 1);
  const ecs::Entity ent = world.create();
  world.emplace<LightningEvent>(ent, e);
  return ent;
}

void add_lightning_system(ecs::Scheduler& s) {
  // The first WeatherScheduler's weather sets how often and where lightning strikes (after the schedulers
  // advanced: weather_systems.h).
  s.add_system(ecs::Phase::Update, "lightning weather", [](ecs::World& w, const ecs::FrameContext&) {
    const weather::LevelWeather* level = w.try_resource<weather::LevelWeather>();
    if (!level || !level->library) return;
    bool first = true;
    w.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& ws) {
      if (!first) return;
      first = false;
      auto* lw = w.try_resource<LightningWeather>();
      if (!lw) lw = &w.set_resource<LightningWeather>();
      const bool encounter_box = ws.encounter_active && ws.has_encounter_lightning_volume;
      lw->per_minute = ws.has_lightning_volume || encounter_box
                           ? weather::weather_now(ws, *level->library).state.lightning_per_minute : 0.0f;
      lw->box_min = encounter_box ? ws.encounter_lightning_min : ws.lightning_min;
      lw->box_max = encounter_box ? ws.encounter_lightning_max : ws.lightning_max;
    });
  });
  s.add_system(ecs::Phase::Update, "lightning", [](ecs::World& w, const ecs::FrameContext& f) {
    const float dt = float(f.dt);
    std::vector<ecs::Entity> expired;
    w.view<LightningEvent>().each([&](ecs::Entity e, LightningEvent& l) {
      l.age_s += dt;
      if (l.age_s >= l.duration_s) expired.push_back(e);
    });
    for (ecs::Entity e : expired) w.destroy(e);
    auto* weather = w.try_resource<LightningWeather>();
    if (!weather || !(weather->per_minute > 0.0f)) return;
    if (!weather->seeded) {
      const auto* seed = w.try_resource<app::SimulationSeed>();
      weather->rng = SplitMix64{hash64("lightning", seed ? seed->value : 1)};
      weather->seeded = true;
    }
    // Poisson arrivals: the chance of a strike in this step (rates far below the step rate).
    const float p = std::min(1.0f, weather->per_minute / 60.0f * dt);
    if (weather->rng.uniform() >= p) return;
    const glm::vec3 r(weather->rng.uniform(), weather->rng.uniform(), weather->rng.uniform());
    const glm::vec3 pos = weather->box_min + (weather->box_max - weather->box_min) * r;
    const LightningKind kind = weather->rng.uniform() < 0.3f ? LightningKind::Ground : LightningKind::Internal;
    strike_lightning(w, pos, kind, 40.0f + 40.0f * weather->rng.uniform());
  });
}

std::vector<LightningLight> lightning_lights(const ecs::World& world, size_t max) {
  std::vector<LightningLight> out;
  world.view<const LightningEvent>().each([&](const LightningEvent& l) {
    const float k = lightning_envelope(l) * l.intensity;
    if (k > 0.0f) out.push_back({l.position, l.radius, k, l.kind, l.seed});
  });
  std::sort(out.begin(), out.end(), [](const LightningLight& a, const LightningLight& b) { return a.intensity > b.intensity; });
  if (out.size() > max) out.resize(max);
  return out;
}

std::vector<BoltSegment> lightning_bolt(glm::vec3 top, float ground_y, uint64_t seed) {
  std::vector<BoltSegment> out;
  const float height = top.y - ground_y;
  if (!(height > 1.0f)) return out;
  SplitMix64 rng{hash64("bolt", seed)};
  auto signed_unit = [&] { return rng.uniform() * 2.0f - 1.0f; };
  // Main channel: equal height steps, each leaning a random way (a tortuous leader, about 30 degrees off
  // the vertical on average), pulled back toward the strike point below the top so it ends near it.
  const glm::vec2 target = glm::vec2(top.x, top.z) + glm::vec2(signed_unit(), signed_unit()) * (0.25f * height);
  const float dy = height / float(kBoltMainSegments);
  std::vector<glm::vec3> main{top};
  for (int i = 1; i <= kBoltMainSegments; ++i) {
    const glm::vec3 p = main.back();
    const float left = float(kBoltMainSegments - i + 1);
    const glm::vec2 pull = (target - glm::vec2(p.x, p.z)) / left;
    const glm::vec2 jag = glm::vec2(signed_unit(), signed_unit()) * (0.6f * dy);
    const glm::vec3 q(p.x + pull.x + jag.x, i == kBoltMainSegments ? ground_y : p.y - dy, p.z + pull.y + jag.y);
    out.push_back({p, q, 1.0f});
    main.push_back(q);
  }
  // Branches: from points on the upper two thirds, down and outward, fading along their length.
  const int branches = 3 + int(rng.uniform() * 3.0f);
  for (int b = 0; b < branches && int(out.size()) < kBoltMaxSegments; ++b) {
    glm::vec3 p = main[1 + size_t(rng.uniform() * float(kBoltMainSegments * 2 / 3))];
    const glm::vec2 out_dir = glm::normalize(glm::vec2(signed_unit(), signed_unit()) + glm::vec2(1e-3f, 0.0f));
    const int n = 4 + int(rng.uniform() * 5.0f);
    for (int k = 0; k < n && int(out.size()) < kBoltMaxSegments && p.y - dy > ground_y; ++k) {
      const glm::vec2 step = out_dir * (0.7f * dy) + glm::vec2(signed_unit(), signed_unit()) * (0.5f * dy);
      const glm::vec3 q(p.x + step.x, p.y - dy * (0.6f + 0.4f * rng.uniform()), p.z + step.y);
      out.push_back({p, q, 0.45f * (1.0f - float(k) / float(n))});
      p = q;
    }
  }
  return out;
}

}  // namespace cumulo::clouds::gameplay
