// libFuzzer target: the weather-state loader. Any text must either load into a state whose numbers are
// finite and in their ranges (so blending it stays finite), or throw cumulo::Error (never crash, hang or
// leak). A cloud_map.png names a file: relative to a folder that does not exist, it is always refused.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/core/error.h"
#include "engine/core/json.h"
#include "modules/clouds/weather/weather_state.h"

using namespace cumulo;
using namespace cumulo::clouds::weather;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const JsonDocument doc = parse_json_text(text, "fuzz.json");
    const WeatherState s = weather_state_from_json(doc.view(), "fuzz", "/nonexistent-cumulo-fuzz/fuzz.json");
    const WeatherState b = blend(s, s, 0.5f).state;
    const float values[] = {b.coverage, b.wind_speed, b.wind_direction.x, b.voxel_density, b.lighting.absorption,
                            b.lighting.phase_forward, b.haze, b.lightning_per_minute};
    for (float v : values)
      if (!std::isfinite(v)) std::abort();
    if (s.coverage < 0.0f || s.coverage > 1.0f || s.cloud_map.octaves < 1 || s.cloud_map.octaves > 8) std::abort();
  } catch (const Error&) {
  }
  return 0;
}
