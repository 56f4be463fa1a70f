#pragma once
// StormbirdDissipation (issue 9; 2023 talk, the Stormbird's death): on its event the storm cloud of the
// same entity dissipates over `duration_s`: the Cloudscape's dissipation rises from its level value to 1,
// which the renderer turns into erosion wisps-first (low-profile, wispy voxels vanish before billowy
// ones) and a light-grid rebuild; the SDF stays valid because the cloud only shrinks. The reset event
// brings it back.
//
//   "StormbirdDissipation": {"event": "stormbird_killed", "reset_event": "stormbird_reset", "duration_s": 20}
#include <string>

#include "engine/core/json.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"

namespace cumulo::clouds::gameplay {

struct StormbirdDissipation {
  std::string event = "stormbird_killed";
  std::string reset_event = "stormbird_reset";
  float duration_s = 20.0f;
  // Runtime.
  bool active = false;
  float progress = 0.0f;  // 0..1, monotonic while active
  float base = -1.0f;     // the Cloudscape's dissipation before the first event (-1: not read yet)
};

StormbirdDissipation stormbird_dissipation_from_json(const JsonView& v);
Json stormbird_dissipation_to_json(const StormbirdDissipation& s);
void register_stormbird_component(ecs::ComponentRegistry& registry);
// Update phase: reacts to the events, advances the dissipation, writes the entity's Cloudscape.
void add_stormbird_system(ecs::Scheduler& s);

}  // namespace cumulo::clouds::gameplay
