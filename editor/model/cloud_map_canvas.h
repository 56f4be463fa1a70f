#pragma once
// Painting on a weather state's cloud map (RGBA8: R coverage, G precipitation, B cloud type; 0.5 in a
// channel is the state's own value, 0 in R a hole). The map tiles in both directions in the sky, so a
// brush that crosses an edge continues on the opposite side. Pure CPU and deterministic: the same dabs
// give the same bytes, which is what lets a script's screenshot be compared with a golden image.
//
//   PaintRect r = paint_dab(map, MapChannel::Coverage, {0.5f, 0.5f}, 0.05f, 0.0f, 1.0f);   // a hole
#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <string_view>

#include "modules/clouds/weather/weather_state.h"

namespace cumulo::editor {

using clouds::weather::PaintedCloudMap;

enum class MapChannel { Coverage, Precipitation, Type };  // R, G, B

// "coverage" | "precipitation" | "type"; nullopt for anything else.
std::optional<MapChannel> parse_map_channel(std::string_view name);
const char* map_channel_name(MapChannel c);
inline int map_channel_index(MapChannel c) { return static_cast<int>(c); }

// Pixels a dab changed, as an unwrapped rectangle [x0, x1) x [y0, y1) in map pixels: it may reach past
// an edge (x0 < 0 or x1 > width), the part outside lying wrapped on the opposite side. Empty when no
// byte changed.
struct PaintRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  void include(const PaintRect& r);
};

// One soft round dab: full strength inside 60% of the radius, then a smoothstep falloff to zero at the
// radius (a hard edge reads as a seam in the sky). Each pixel of the channel moves toward `value` by
// strength * falloff, so repeated weak dabs build up the way an airbrush does.
//   uv: 0..1 across the map (wrapped; (0,0) the top-left pixel's corner, the PNG's layout)
//   radius: in uv units of the map's width (0.05 = 5% of the width), the same in pixels on both axes
//   value, strength: clamped to 0..1
// A map whose rgba size is not width*height*4 is left alone (per-frame code does not throw).
PaintRect paint_dab(PaintedCloudMap& map, MapChannel channel, glm::vec2 uv, float radius, float value,
                    float strength = 1.0f);

// The brush's weight at distance/radius t (1 inside 0.6, 0 from 1); exposed for the UI's brush preview.
float brush_falloff(float t);

}  // namespace cumulo::editor
