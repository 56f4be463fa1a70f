#pragma once
// The ECS in one include (all light: standard headers only).
//   entity.h     ecs::Entity {index, generation}: generational handles; stale ones are detected
//   world.h      ecs::World: components (sparse sets), view<const A, B>().each(...), defer(), Name, events,
//                resources; the rules for iteration and deferral are at its top
//   events.h     EventQueue<T> (double-buffered per step), EventReader<T> (per-system cursor)
//   scheduler.h  Scheduler: systems in phases Input, PreUpdate, Update, PostUpdate, Extract; FrameContext
// Not included here because it pulls in nlohmann/json: serialize.h (ComponentRegistry, serialize_world,
// load_entities) for modules that register components and for loaders.
#include "engine/ecs/entity.h"
#include "engine/ecs/events.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/world.h"
