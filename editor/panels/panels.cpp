#include "editor/panels/panels.h"

namespace cumulo::editor {

std::vector<PanelInfo>& panels() {
  // Left column: the state being edited; right column: the world's components; bottom: paint and cost.
  static std::vector<PanelInfo> list = {
      {"Weather states", draw_weather_panel, true, {0, 20}, {330, 520}},
      {"Scheduler & zones", draw_scheduler_panel, true, {950, 20}, {330, 230}},
      {"Time of day", draw_time_panel, true, {950, 252}, {330, 96}},
      {"Cloudscapes", draw_cloudscape_panel, true, {950, 350}, {330, 190}},
      {"Orographic clouds", draw_envelope_panel, false, {620, 20}, {328, 300}},
      {"Cloud map", draw_paint_panel, true, {0, 542}, {330, 150}},
      {"Events & triggers", draw_events_panel, true, {950, 542}, {330, 150}},
      {"Performance", draw_performance_panel, true, {332, 542}, {616, 150}},
  };
  return list;
}

bool begin_panel(PanelInfo& p) {
  // The layout is made for 1280x720 and scaled to the window the first time a panel appears.
  const ImVec2 vp = ImGui::GetMainViewport()->Size;
  const float sx = vp.x / 1280.0f, sy = vp.y / 720.0f;
  ImGui::SetNextWindowPos(ImVec2(p.pos.x * sx, p.pos.y * sy), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(p.size.x * sx, p.size.y * sy), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  return ImGui::Begin(p.title, &p.open);
}

bool world_to_screen(const Editor& e, glm::vec3 p, ImVec2& out) {
  const glm::vec4 c = e.camera.view_proj * glm::vec4(p, 1.0f);
  if (c.w <= 1e-3f) return false;
  const ImVec2 size = ImGui::GetMainViewport()->Size;
  out = ImVec2((c.x / c.w * 0.5f + 0.5f) * size.x, (c.y / c.w * 0.5f + 0.5f) * size.y);
  return true;
}

void item_tooltip(const char* text) {
  if (text && *text && ImGui::IsItemHovered()) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
    ImGui::TextUnformatted(text);
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
  }
}

}  // namespace cumulo::editor
