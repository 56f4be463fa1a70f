#pragma once
// Lightning (issue 9; 2023 talk: the Stormbird's storm lit from inside, "lightning potential energy"):
// a LightningEvent entity is one flash, ground discharge or internal (in-cloud) flash, at a position
// with a radius and an intensity over its short life (a fast rise, a flickering decay). The renderer
// takes the brightest live flashes as its point lights (the talk's potential-energy field); the weather
// spawns them at its `lightning.frequency_per_minute` inside the cloudscape, game code with
// strike_lightning(). Deterministic for the seed.
//
//   "LightningEvent": {"kind": "internal", "position": [0, 900, 0], "radius": 400, "intensity": 60, "duration_s": 0.8}
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/enum_names.h"
#include "engine/core/json.h"
#include "engine/core/random.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"
#include "engine/ecs/world.h"

namespace cumulo::clouds::gameplay {

enum class LightningKind : uint8_t { Ground, Internal };
inline constexpr std::array kLightningKindNames{EnumName<LightningKind>{LightningKind::Ground, "ground"},
                                                EnumName<LightningKind>{LightningKind::Internal, "internal"}};

struct LightningEvent {
  LightningKind kind = LightningKind::Internal;
  glm::vec3 position{0.0f};
  float radius = 400.0f;     // m: the glow's reach
  float intensity = 60.0f;   // peak colour multiplier
  float duration_s = 0.8f;
  float age_s = 0.0f;        // runtime
  uint64_t seed = 1;         // flicker stream
};

LightningEvent lightning_event_from_json(const JsonView& v);
Json lightning_event_to_json(const LightningEvent& e);
void register_lightning_component(ecs::ComponentRegistry& registry);

// The flash's intensity multiplier at its age: 0 before 0 and after duration_s, a 30 ms rise, then a
// decay with 3-5 re-strokes (the flicker), deterministic for the seed.
float lightning_envelope(const LightningEvent& e);

ecs::Entity strike_lightning(ecs::World& world, glm::vec3 position, LightningKind kind = LightningKind::Internal,
                             float intensity = 60.0f, float radius = 400.0f);

// Where and how often the weather spawns flashes: set each step from the first WeatherScheduler's weather.
struct LightningWeather {
  float per_minute = 0.0f;
  glm::vec3 box_min{0.0f}, box_max{0.0f};  // spawn volume (the first cloudscape's world box, lower half)
  SplitMix64 rng;
  bool seeded = false;
};

// Update phase, after the weather schedulers: LightningWeather from the weather now ("lightning weather"),
// then spawns (Poisson at LightningWeather::per_minute), ages and removes flashes ("lightning").
void add_lightning_system(ecs::Scheduler& s);

struct LightningLight {
  glm::vec3 position;
  float radius;
  float intensity;  // envelope x peak intensity now
  LightningKind kind = LightningKind::Internal;
  uint64_t seed = 1;
};
// The live flashes, brightest first, at most `max` (the renderer's point-light list).
std::vector<LightningLight> lightning_lights(const ecs::World& world, size_t max);

// The visible channel of a ground discharge: a branching path from the flash's position down to
// `ground_y`, as segments (a main channel of kBoltMainSegments jagged steps, then a few shorter branches
// leaving it downward). Deterministic for the seed; every segment lies between ground_y and the top.
struct BoltSegment {
  glm::vec3 a, b;
  float brightness;  // 1 on the main channel, less on branches
};
inline constexpr int kBoltMainSegments = 28;
inline constexpr int kBoltMaxSegments = 64;
std::vector<BoltSegment> lightning_bolt(glm::vec3 top, float ground_y, uint64_t seed);

}  // namespace cumulo::clouds::gameplay
