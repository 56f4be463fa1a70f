// libFuzzer target: the cloud module's level components (WeatherScheduler, WeatherZone, Trigger,
// LightningEvent, StormbirdDissipation). Any JSON must either parse into a component whose numbers stay
// finite and in range, or throw cumulo::Error (never crash, hang or leak). The first byte picks the
// component; a parsed scheduler is also advanced for a few steps.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/core/error.h"
#include "engine/core/json.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

using namespace cumulo;
using namespace cumulo::clouds;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const JsonDocument doc = parse_json_text(text, "fuzz.json");
    switch (data[0] % 5) {
      case 0: {
        weather::WeatherScheduler s = weather::weather_scheduler_from_json(doc.view());
        for (int i = 0; i < 64; ++i) weather::advance(s, 1.0f, float(i % 24), 1);
        if (!std::isfinite(s.t) || !std::isfinite(s.hold_left) || s.current.empty()) std::abort();
        break;
      }
      case 1: {
        const weather::WeatherZone z = weather::weather_zone_from_json(doc.view());
        if (!std::isfinite(z.volume()) || z.states.empty()) std::abort();
        break;
      }
      case 2: (void)gameplay::trigger_from_json(doc.view()); break;
      case 3: {
        gameplay::LightningEvent e = gameplay::lightning_event_from_json(doc.view());
        for (float t = 0.0f; t < 2.0f; t += 0.05f) {
          e.age_s = t;
          const float k = gameplay::lightning_envelope(e);
          if (!(k >= 0.0f && k <= 1.0f)) std::abort();
        }
        break;
      }
      case 4: (void)gameplay::stormbird_dissipation_from_json(doc.view()); break;
    }
  } catch (const Error&) {
  }
  return 0;
}
