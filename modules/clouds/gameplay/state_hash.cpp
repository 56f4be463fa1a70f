#include "modules/clouds/gameplay/state_hash.h"

#include <cstring>
#include <string>

#include "engine/core/hash.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/weather/weather_scheduler.h"

namespace cumulo::clouds::gameplay {
namespace {

struct Hasher {
  uint64_t h = kFnvOffset;
  template <typename T>
  void pod(const T& v) {
    h = hash64(&v, sizeof v, h);
  }
  void str(const std::string& s) {
    pod(s.size());
    h = hash64(s.data(), s.size(), h);
  }
};

}  // namespace

uint64_t cloud_state_hash(const ecs::World& world) {
  Hasher x;
  world.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& s) {
    x.str(s.current), x.str(s.next), x.str(s.zone);
    x.pod(s.t), x.pod(s.transition_duration), x.pod(s.hold_left), x.pod(s.rng.state), x.pod(s.transitions);
    x.pod(s.encounter_active);
  });
  world.view<const LightningEvent>().each([&](const LightningEvent& l) {
    x.pod(l.position), x.pod(l.age_s), x.pod(l.intensity), x.pod(l.seed), x.pod(l.kind);
  });
  if (const auto* lw = world.try_resource<LightningWeather>()) x.pod(lw->rng.state), x.pod(lw->per_minute);
  world.view<const Cloudscape>().each([&](const Cloudscape& c) { x.pod(c.dissipation), x.pod(c.density); });
  world.view<const StormbirdDissipation>().each([&](const StormbirdDissipation& d) { x.pod(d.progress), x.pod(d.active); });
  world.view<const CloudGrowth>().each([&](const CloudGrowth& g) {
    x.pod(g.running), x.pod(g.ended), x.pod(g.sim_seconds), x.pod(g.target_steps), x.pod(g.generation);
  });
  world.view<const Trigger>().each([&](const Trigger& t) { x.pod(t.inside), x.pod(t.fired), x.pod(t.primed); });
  return x.h;
}

}  // namespace cumulo::clouds::gameplay
