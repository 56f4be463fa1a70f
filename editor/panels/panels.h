#pragma once
// The editor's panels: one ImGui window per component of the cloud module (DESIGN.md's editor; STYLE.md:
// "one editor panel per component"), each a free function over the Editor. panels() is the one list
// (the View menu, the layout, the "every panel open" cost measurement go through it).
//
//   Weather states     list / create / duplicate / rename / delete, every parameter, blend preview
//   Scheduler & zones  current / next state, progress, force a transition, the camera's zone, schedules
//   Time of day        hours, speed, pause
//   Cloudscapes        transforms, asset, density, dissipation, rain, renderer debug views
//   Orographic clouds  the Envelope method's components: density, coverage, edge, wind, each rule's heights
//   Cloud map          a top-down view of the state's map and a brush painting coverage / type
//   Events & triggers  lightning at the camera's target, named events, dissipation reset, live lists
//   Performance        per-pass GPU times, frame-time plot, budget mode, the render graph's passes
#include <imgui.h>
#include <imgui_internal.h>  // ImGui::GetItemID

#include <vector>

#include "editor/editor.h"

namespace cumulo::editor {

struct PanelInfo {
  const char* title;
  void (*draw)(Editor&, PanelInfo&);
  bool open = true;
  ImVec2 pos, size;  // first-use layout for a 1280x720 window
};

std::vector<PanelInfo>& panels();

void draw_weather_panel(Editor& e, PanelInfo& p);
void draw_scheduler_panel(Editor& e, PanelInfo& p);
void draw_time_panel(Editor& e, PanelInfo& p);
void draw_cloudscape_panel(Editor& e, PanelInfo& p);
void draw_envelope_panel(Editor& e, PanelInfo& p);
void draw_paint_panel(Editor& e, PanelInfo& p);
void draw_events_panel(Editor& e, PanelInfo& p);
void draw_performance_panel(Editor& e, PanelInfo& p);
// Trigger volumes, zones and live lightning drawn over the viewport (the background draw list).
void draw_viewport_overlay(Editor& e);
// The cloudscapes' move handles in the viewport (drag with the left button; gizmo.cpp).
void draw_cloudscape_handles(Editor& e);

// Makes the last widget's change of `field` of component T on `entity` undoable: `before` is the field
// as it was before the widget this frame, `changed` what the widget returned. A drag is one step (from
// its activation to its release); a click (a checkbox, a combo item) is one step at once.
template <class T, class V>
void world_edit(Editor& e, ecs::Entity entity, V T::*field, const V& before, bool changed, const char* label) {
  auto restore = [entity, field](V value) {
    return [entity, field, value](ecs::World& w) {
      if (T* c = w.try_get<T>(entity)) c->*field = value;
    };
  };
  const ImGuiID id = ImGui::GetItemID();
  if (ImGui::IsItemActivated()) e.world_drag = {{id, restore(before)}};
  const T* now = static_cast<const ecs::World&>(e.world()).try_get<T>(entity);
  if (!now) return;
  if (ImGui::IsItemDeactivatedAfterEdit() && e.world_drag && e.world_drag->first == id) {
    e.push_world_edit(label, e.world_drag->second, restore(now->*field));
    e.world_drag.reset();
  } else if (changed && !ImGui::IsItemActive()) {
    e.push_world_edit(label, restore(before), restore(now->*field));
  }
}

// A world point on the viewport (the last extracted frame's camera); false when behind the camera.
bool world_to_screen(const Editor& e, glm::vec3 p, ImVec2& out);

// ImGui::Begin at the panel's first-use place; false when collapsed (End() is still to be called).
bool begin_panel(PanelInfo& p);
// A "(?)" marker with `text` as its tooltip, or the last item's tooltip when hovered.
void item_tooltip(const char* text);

}  // namespace cumulo::editor
