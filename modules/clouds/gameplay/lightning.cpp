#include "modules/clouds/gameplay/lightning.h"

#include <algorithm>
#include <cstring>
#include <cmath>

#include "engine/app/simulation.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"

namespace cumulo::clouds::gameplay {

LightningEvent lightning_event_from_json(const JsonView& v) {
  for (const std::string& k : v.keys())
    if (k != "kind" && k != "position" && k != "radius" && k != "intensity" && k != "duration_s")
      v.fail("unknown key \"" + k + "\" (expected kind, position, radius, intensity, duration_s)");
  LightningEvent e;
  if (v.has("kind")) e.kind = v["kind"].as_enum({"ground", "internal"}) == 0 ? LightningKind::Ground : LightningKind::Internal;
  e.position = v["position"].as_vec3();
  if (v.has("radius")) e.radius = v["radius"].as_float_in(1.0f, 1e5f);
  if (v.has("intensity")) e.intensity = v["intensity"].as_float_in(0.0f, 1e6f);
  if (v.has("duration_s")) e.duration_s = v["duration_s"].as_float_in(0.01f, 60.0f);
  e.seed = hash64(v.where());
  return e;
}

Json lightning_event_to_json(const LightningEvent& e) {
  return {{"kind", e.kind == LightningKind::Ground ? "ground" : "internal"},
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

ecs::Entity strike_lightning(ecs::World& world, glm::vec3 position, LightningKind kind, float intensity) {
  LightningEvent e;
  e.kind = kind;
  e.position = position;
  e.intensity = intensity;
  const auto* seed = world.try_resource<app::SimulationSeed>();
  uint64_t p[4];
  std::memcpy(p, &position, sizeof position);
  p[3] = world.alive_count();
  e.seed = hash64(p, sizeof p, seed ? seed->value : 1);
  const ecs::Entity ent = world.create();
  world.emplace<LightningEvent>(ent, e);
  return ent;
}

void add_lightning_system(ecs::Scheduler& s) {
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
    if (k > 0.0f) out.push_back({l.position, l.radius, k});
  });
  std::sort(out.begin(), out.end(), [](const LightningLight& a, const LightningLight& b) { return a.intensity > b.intensity; });
  if (out.size() > max) out.resize(max);
  return out;
}

}  // namespace cumulo::clouds::gameplay
