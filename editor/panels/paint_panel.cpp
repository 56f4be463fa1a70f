// The cloud map panel: the edited state's map seen from above (R coverage as cloud over blue, or the
// painted channel alone), the camera's place on it, and a brush that paints coverage, type or
// precipitation (the 2017 talk: "I want a hole right here"). A stroke is one undo step; the painting
// is in the sky within the frame and saved as <state>.cloud_map.png beside the state.
#include <imgui.h>

#include <cmath>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "engine/core/error.h"
#include "modules/clouds/render/sky_layer.h"

namespace cumulo::editor {
namespace {

constexpr int kCells = 64;  // the view's resolution: enough to aim a brush, cheap to draw every frame

struct MapPreview {
  clouds::weather::CloudMapSource source;
  bool valid = false;
  float cells[kCells * kCells][3];  // R, G, B in 0..1
};

// The map's pixels averaged into the view's cells; remade only when the state's map source changes.
void update_preview(MapPreview& p, const clouds::weather::CloudMapSource& src) {
  if (p.valid && p.source == src) return;
  clouds::render::CloudMapImage m;
  try {
    m = clouds::render::make_cloud_map(src, kCells);  // procedural: the same field at the view's resolution
  } catch (const Error&) {
    m = {};
  }
  p.source = src;
  p.valid = true;
  for (int cy = 0; cy < kCells; ++cy)
    for (int cx = 0; cx < kCells; ++cx) {
      float sum[3] = {0, 0, 0};
      int n = 0;
      if (m.width && m.height) {
        const uint32_t x0 = uint32_t(cx) * m.width / kCells, x1 = std::max(x0 + 1, uint32_t(cx + 1) * m.width / kCells);
        const uint32_t y0 = uint32_t(cy) * m.height / kCells, y1 = std::max(y0 + 1, uint32_t(cy + 1) * m.height / kCells);
        for (uint32_t y = y0; y < y1; ++y)
          for (uint32_t x = x0; x < x1; ++x, ++n)
            for (int c = 0; c < 3; ++c) sum[c] += m.rgba[(size_t(y) * m.width + x) * 4 + size_t(c)];
      }
      for (int c = 0; c < 3; ++c) p.cells[cy * kCells + cx][c] = n ? sum[c] / (255.0f * float(n)) : 0.0f;
    }
}

ImU32 cell_colour(const float* rgb, MapChannel view) {
  auto mix = [](float a, float b, float t) { return a + (b - a) * t; };
  if (view == MapChannel::Coverage) {
    // Cloud over sky: 0 (a hole) deep blue, 0.5 (the state's coverage) light, 1 white.
    const float c = std::min(1.0f, rgb[0]);
    return ImGui::ColorConvertFloat4ToU32(ImVec4(mix(0.12f, 1.0f, c), mix(0.25f, 1.0f, c), mix(0.55f, 1.0f, c), 1.0f));
  }
  const float v = rgb[map_channel_index(view)];
  return view == MapChannel::Type ? ImGui::ColorConvertFloat4ToU32(ImVec4(v, 0.6f * v + 0.2f, 1.0f - v, 1.0f))
                                  : ImGui::ColorConvertFloat4ToU32(ImVec4(0.2f, 0.3f + 0.5f * v, 0.2f + 0.8f * v, 1.0f));
}

}  // namespace

void draw_paint_panel(Editor& e, PanelInfo& panel) {
  static MapPreview preview;
  static glm::vec2 last_uv{-1.0f};
  if (!begin_panel(panel)) return ImGui::End();
  const std::string id = e.target_state();
  if (id.empty()) {
    ImGui::TextDisabled("No weather state to paint.");
    return ImGui::End();
  }
  WeatherDocument& doc = e.document();
  const clouds::weather::WeatherState state = doc.state(id);
  update_preview(preview, state.cloud_map);

  // Brush settings beside the map.
  const float side = std::max(64.0f, std::min(ImGui::GetContentRegionAvail().y, ImGui::GetContentRegionAvail().x - 170.0f));
  ImGui::BeginGroup();
  ImGui::PushItemWidth(110.0f);
  static const char* kChannels[] = {"coverage", "precipitation", "type"};
  int ch = map_channel_index(e.brush_channel);
  if (ImGui::Combo("paints", &ch, kChannels, 3)) e.brush_channel = MapChannel(ch);
  ImGui::SliderFloat("value", &e.brush_value, 0.0f, 1.0f, "%.2f");
  item_tooltip("What the brush paints toward: 0 coverage is a hole, 0.5 the state's own value, 1 the most.");
  ImGui::SliderFloat("size", &e.brush_radius, 0.005f, 0.5f, "%.3f");
  item_tooltip("The brush's radius, as a fraction of the map (one map tiles 4 x scale_km).");
  ImGui::SliderFloat("strength", &e.brush_strength, 0.05f, 1.0f, "%.2f");
  ImGui::PopItemWidth();
  ImGui::TextDisabled("%s%s", id.c_str(), state.cloud_map.painted ? " (painted)" : state.cloud_map.png.empty() ? " (procedural)" : " (PNG)");
  ImGui::EndGroup();
  ImGui::SameLine();

  // The map, top-down: +x right, +z down (the PNG's rows), one tile.
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("map", ImVec2(side, side));
  const bool hovered = ImGui::IsItemHovered(), active = ImGui::IsItemActive();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float cell = side / kCells;
  dl->PrimReserve(kCells * kCells * 6, kCells * kCells * 4);
  for (int y = 0; y < kCells; ++y)
    for (int x = 0; x < kCells; ++x)
      dl->PrimRect(ImVec2(p0.x + x * cell, p0.y + y * cell), ImVec2(p0.x + (x + 1) * cell, p0.y + (y + 1) * cell),
                   cell_colour(preview.cells[y * kCells + x], e.brush_channel));
  // The camera's place on the map (drift with the wind as the sky layer's lookup does).
  const float tile = 4.0f * std::max(state.cloud_map.scale_km, 0.1f) * 1000.0f;
  const glm::vec2 drift = glm::vec2(state.wind_direction.x, state.wind_direction.z) * float(state.wind_speed * e.sim_time);
  const glm::vec2 cam = (glm::vec2(e.camera.position.x, e.camera.position.z) - drift) / tile;
  const glm::vec2 cuv = cam - glm::floor(cam);
  const ImVec2 cp(p0.x + cuv.x * side, p0.y + cuv.y * side);
  glm::vec2 fwd(e.camera.forward.x, e.camera.forward.z);
  if (glm::length(fwd) > 1e-3f) fwd = glm::normalize(fwd);
  dl->AddCircleFilled(cp, 4.0f, IM_COL32(255, 80, 60, 255));
  dl->AddLine(cp, ImVec2(cp.x + fwd.x * 14.0f, cp.y + fwd.y * 14.0f), IM_COL32(255, 80, 60, 255), 2.0f);
  dl->AddRect(p0, ImVec2(p0.x + side, p0.y + side), IM_COL32(200, 200, 200, 120));
  if (hovered || active) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    dl->AddCircle(m, e.brush_radius * side, IM_COL32(255, 255, 255, 200), 32);
    const glm::vec2 uv((m.x - p0.x) / side, (m.y - p0.y) / side);
    if (active) {
      try {
        if (ImGui::IsItemActivated() || last_uv.x < 0.0f) {
          doc.begin_stroke(id);
          doc.paint(id, e.brush_channel, uv, e.brush_radius, e.brush_value, e.brush_strength);
        } else if (glm::length(uv - last_uv) > 0.25f * e.brush_radius) {
          doc.paint_line(id, e.brush_channel, last_uv, uv, e.brush_radius, e.brush_value, e.brush_strength);
        } else {
          doc.paint(id, e.brush_channel, uv, e.brush_radius, e.brush_value, e.brush_strength * 0.25f);
        }
        last_uv = uv;
        e.sync_live();
      } catch (const Error& err) {
        e.message(EditorMessage::Level::Error, err.what());
      }
    }
  }
  if (ImGui::IsItemDeactivated() && doc.in_stroke()) {
    doc.end_stroke();
    last_uv = glm::vec2(-1.0f);
    e.sync_live();
  }
  ImGui::End();
}

}  // namespace cumulo::editor
