#include "editor/model/cloud_map_canvas.h"

#include <algorithm>
#include <cmath>

namespace cumulo::editor {
namespace {

constexpr float kHardCore = 0.6f;  // fraction of the radius painted at full strength

int wrap(int i, int n) { return ((i % n) + n) % n; }

// The shorter way around a tiling axis of n pixels.
float toroidal(float d, float n) {
  d = std::fabs(d);
  d = std::fmod(d, n);
  return std::min(d, n - d);
}

}  // namespace

std::optional<MapChannel> parse_map_channel(std::string_view name) {
  if (name == "coverage") return MapChannel::Coverage;
  if (name == "precipitation") return MapChannel::Precipitation;
  if (name == "type") return MapChannel::Type;
  return std::nullopt;
}

const char* map_channel_name(MapChannel c) {
  switch (c) {
    case MapChannel::Coverage:
      return "coverage";
    case MapChannel::Precipitation:
      return "precipitation";
    case MapChannel::Type:
      return "type";
  }
  return "?";
}

void PaintRect::include(const PaintRect& r) {
  if (r.empty()) return;
  if (empty()) {
    *this = r;
    return;
  }
  x0 = std::min(x0, r.x0);
  y0 = std::min(y0, r.y0);
  x1 = std::max(x1, r.x1);
  y1 = std::max(y1, r.y1);
}

float brush_falloff(float t) {
  if (t <= kHardCore) return 1.0f;
  if (t >= 1.0f) return 0.0f;
  const float s = (t - kHardCore) / (1.0f - kHardCore);
  return 1.0f - s * s * (3.0f - 2.0f * s);
}

PaintRect paint_dab(PaintedCloudMap& map, MapChannel channel, glm::vec2 uv, float radius, float value, float strength) {
  PaintRect changed;
  const int w = int(map.width), h = int(map.height);
  if (w <= 0 || h <= 0 || map.rgba.size() != size_t(w) * size_t(h) * 4) return changed;
  if (!(radius > 0.0f) || !std::isfinite(uv.x) || !std::isfinite(uv.y)) return changed;
  value = std::clamp(std::isfinite(value) ? value : 0.0f, 0.0f, 1.0f);
  strength = std::clamp(std::isfinite(strength) ? strength : 0.0f, 0.0f, 1.0f);
  uv -= glm::floor(uv);
  // At least a pixel, so a tiny brush still paints the pixel under the cursor.
  const float r = std::max(radius * float(w), 1.0f);
  const float cx = uv.x * float(w), cy = uv.y * float(h);
  // The unwrapped box, at most one map wide: each pixel is visited once and its distance taken the
  // short way around, so a brush larger than the map does not paint a pixel twice.
  int bx0 = int(std::floor(cx - r)), by0 = int(std::floor(cy - r));
  int bx1 = std::min(int(std::ceil(cx + r)) + 1, bx0 + w), by1 = std::min(int(std::ceil(cy + r)) + 1, by0 + h);
  const int c = map_channel_index(channel);
  for (int y = by0; y < by1; ++y) {
    const float dy = toroidal(float(y) + 0.5f - cy, float(h));
    for (int x = bx0; x < bx1; ++x) {
      const float dx = toroidal(float(x) + 0.5f - cx, float(w));
      const float f = brush_falloff(std::sqrt(dx * dx + dy * dy) / r) * strength;
      if (f <= 0.0f) continue;
      uint8_t& byte = map.rgba[(size_t(wrap(y, h)) * size_t(w) + size_t(wrap(x, w))) * 4 + size_t(c)];
      const float cur = float(byte) / 255.0f;
      const float next = cur + (value - cur) * f;
      const uint8_t out = uint8_t(std::clamp(std::lround(next * 255.0f), 0l, 255l));
      if (out == byte) continue;
      byte = out;
      changed.include({x, y, x + 1, y + 1});
    }
  }
  return changed;
}

}  // namespace cumulo::editor
