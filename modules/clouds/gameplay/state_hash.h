#pragma once
// A hash of the cloud module's simulation state (weather schedulers, zones in effect, lightning flashes, triggers,
// dissipation): two runs with the same level, seed and events must agree on it after every step (the
// replay determinism of issue 9). Floats are hashed by their bits: "the same" means bit-identical.
#include <cstdint>

#include "engine/ecs/world.h"

namespace cumulo::clouds::gameplay {

uint64_t cloud_state_hash(const ecs::World& world);

}  // namespace cumulo::clouds::gameplay
