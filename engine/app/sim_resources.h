#pragma once
// The world resources a run sets for its systems. Apart from simulation.h so that gameplay and weather
// code reaches them without the module interface (and through it the render graph and Vulkan).
#include <cstdint>

#include "engine/ecs/world.h"

namespace cumulo::app {

// World resource: the run's random seed. Systems that need randomness derive their streams from it
// (e.g. hash64(seed, system name, step)), never from the wall clock.
struct SimulationSeed {
  uint64_t value = 1;
};

// World resource: the entity the run views the world from (the camera of `--camera`, the one the
// windowed run flies). Gameplay that depends on where the player is (weather zones, triggers) reads its
// Transform. Absent in a world nobody views (tools, tests that set no viewer).
struct Viewer {
  ecs::Entity entity;
};

}  // namespace cumulo::app
