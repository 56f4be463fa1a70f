// Events and triggers: lightning at the camera's target, the level's named events, the Stormbird's
// dissipation reset, and what is live (flashes, triggers); the viewport overlay draws the triggers'
// volumes, the weather zones and the live flashes where they are in the world.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <set>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "engine/app/game_events.h"
#include "modules/clouds/gameplay/cloud_growth.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/stormbird.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::editor {
namespace {

// The events the level reacts to: those its triggers wait for and its dissipations' events.
std::vector<std::string> level_events(const ecs::World& w) {
  std::set<std::string> names;
  w.view<const clouds::gameplay::Trigger>().each([&](const clouds::gameplay::Trigger& t) {
    if (t.when == clouds::gameplay::Trigger::When::Event && !t.event.empty()) names.insert(t.event);
    for (const auto& a : t.actions)
      if (a.kind == clouds::gameplay::TriggerAction::Kind::FireEvent) names.insert(a.text);
  });
  w.view<const clouds::gameplay::StormbirdDissipation>().each([&](const clouds::gameplay::StormbirdDissipation& s) {
    names.insert(s.event);
    names.insert(s.reset_event);
  });
  w.view<const clouds::gameplay::CloudGrowth>().each([&](const clouds::gameplay::CloudGrowth& g) {
    names.insert(g.event);
    names.insert(g.reset_event);
  });
  names.erase("");
  return {names.begin(), names.end()};
}

const char* when_name(clouds::gameplay::Trigger::When w) {
  switch (w) {
    case clouds::gameplay::Trigger::When::Enter: return "enter";
    case clouds::gameplay::Trigger::When::Exit: return "exit";
    case clouds::gameplay::Trigger::When::Event: return "event";
    case clouds::gameplay::Trigger::When::Time: return "time";
  }
  return "?";
}

void draw_box(const Editor& e, ImDrawList* dl, glm::vec3 lo, glm::vec3 hi, ImU32 colour) {
  static const int kEdges[12][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}, {4, 5}, {5, 7}, {7, 6}, {6, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  glm::vec3 corner[8];
  for (int i = 0; i < 8; ++i) corner[i] = glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  for (const auto& edge : kEdges) {
    ImVec2 a, b;
    if (world_to_screen(e, corner[edge[0]], a) && world_to_screen(e, corner[edge[1]], b)) dl->AddLine(a, b, colour, 1.5f);
  }
}

void draw_sphere(const Editor& e, ImDrawList* dl, glm::vec3 c, float r, ImU32 colour) {
  // Three great circles.
  for (int axis = 0; axis < 3; ++axis) {
    ImVec2 prev;
    bool have = false;
    for (int i = 0; i <= 32; ++i) {
      const float a = float(i) / 32.0f * 6.2831853f;
      glm::vec3 o(0.0f);
      o[axis] = std::cos(a) * r;
      o[(axis + 1) % 3] = std::sin(a) * r;
      ImVec2 s;
      const bool ok = world_to_screen(e, c + o, s);
      if (ok && have) dl->AddLine(prev, s, colour, 1.5f);
      prev = s;
      have = ok;
    }
  }
}

void draw_volume(const Editor& e, ImDrawList* dl, const clouds::gameplay::TriggerVolume& v, ImU32 colour) {
  if (v.sphere) draw_sphere(e, dl, v.center, v.radius, colour);
  else draw_box(e, dl, v.min, v.max, colour);
}

// The clouds that grow during play (issue 26): where each simulation is (its step of the spec's last, the physical
// time simulated), and pause, a single step while paused, start and reset. The component's system does the rest
// (cloud_growth.h): the renderer follows its target step.
void draw_growths(Editor& e, ecs::World& w) {
  w.view<clouds::gameplay::CloudGrowth>().each([&](ecs::Entity ent, clouds::gameplay::CloudGrowth& g) {
    ImGui::PushID(&g);
    const char* state = clouds::gameplay::cloud_growth_state(g);
    const auto* n = w.try_get<ecs::Name>(ent);
    ImGui::Text("%s: step %d / %d (%.0f s simulated), %s", n ? n->value.c_str() : "growing cloud", g.target_steps,
                g.last_step, g.sim_seconds, state);
    if (!g.running && !g.ended) {
      if (ImGui::SmallButton("Start")) g.running = true;
      item_tooltip("Starts the growth now (its event or weather state would too).");
      ImGui::SameLine();
    }
    if (ImGui::Checkbox("Paused", &g.paused)) e.message(EditorMessage::Level::Info, g.paused ? "growth paused" : "growth resumed");
    ImGui::SameLine();
    ImGui::BeginDisabled(!clouds::gameplay::cloud_growth_can_step_once(g));
    if (ImGui::SmallButton("Step")) g.step_once = true;
    ImGui::EndDisabled();
    item_tooltip("While paused: one more simulation step.");
    ImGui::SameLine();
    if (ImGui::SmallButton("Reset")) clouds::gameplay::request_cloud_growth_reset(w, g, e.sim_time);
    item_tooltip("Back to the first step (its reset event when it has one).");
    ImGui::PopID();
  });
}

}  // namespace

void draw_events_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  ecs::World& w = e.world();
  static int kind = 0;
  static float intensity = 60.0f, radius = 400.0f;
  if (ImGui::Button("Lightning at the camera's target")) {
    const glm::vec3 at = e.camera.position + e.camera.forward * e.target_distance;
    clouds::gameplay::strike_lightning(w, at, kind ? clouds::gameplay::LightningKind::Ground
                                                   : clouds::gameplay::LightningKind::Internal, intensity, radius);
    e.message(EditorMessage::Level::Info, strf("lightning at (%.0f, %.0f, %.0f)", at.x, at.y, at.z));
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80.0f);
  ImGui::Combo("##kind", &kind, "internal\0ground\0");
  ImGui::PushItemWidth(110.0f);
  ImGui::DragFloat("target m", &e.target_distance, 10.0f, 50.0f, 20000.0f, "%.0f");
  item_tooltip("How far along the view the flash strikes.");
  ImGui::SameLine();
  ImGui::DragFloat("intensity", &intensity, 1.0f, 1.0f, 500.0f, "%.0f");
  ImGui::PopItemWidth();
  for (const std::string& name : level_events(w)) {
    if (ImGui::SmallButton(name.c_str())) {
      app::schedule_event(w, name, e.sim_time);  // input from outside the simulation: recorded like a key
      e.message(EditorMessage::Level::Info, "event " + name);
    }
    ImGui::SameLine();
  }
  ImGui::NewLine();
  if (ImGui::SmallButton("Reset dissipation")) {
    std::vector<std::string> resets;
    w.view<const clouds::gameplay::StormbirdDissipation>().each(
        [&](const clouds::gameplay::StormbirdDissipation& s) { resets.push_back(s.reset_event); });
    for (const std::string& r : resets) app::schedule_event(w, r, e.sim_time);
  }
  item_tooltip("Fires every StormbirdDissipation's reset event: the storm cloud comes back.");
  int flashes = 0;
  w.view<const clouds::gameplay::LightningEvent>().each([&](const clouds::gameplay::LightningEvent& l) {
    ++flashes;
    if (ImGui::TreeNodeEx(&l, ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen, "flash %s at (%.0f, %.0f, %.0f), %.2f/%.2f s",
                          name_of(clouds::gameplay::kLightningKindNames, l.kind), l.position.x,
                          l.position.y, l.position.z, l.age_s, l.duration_s)) {
    }
  });
  if (!flashes) ImGui::TextDisabled("no live lightning");
  draw_growths(e, w);
  if (ImGui::TreeNode("Triggers")) {
    w.view<const clouds::gameplay::Trigger>().each([&](ecs::Entity ent, const clouds::gameplay::Trigger& t) {
      const auto* n = w.try_get<ecs::Name>(ent);
      ImGui::BulletText("%s: on %s%s%s, %zu actions%s", n ? n->value.c_str() : "trigger", when_name(t.when),
                        t.event.empty() ? "" : " ", t.event.c_str(), t.actions.size(),
                        t.fired && t.once ? " (fired)" : t.inside ? " (camera inside)" : "");
    });
    ImGui::TreePop();
  }
  ImGui::End();
}

void draw_viewport_overlay(Editor& e) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const ecs::World& w = e.world();
  w.view<const clouds::gameplay::Trigger>().each([&](const clouds::gameplay::Trigger& t) {
    if (t.when == clouds::gameplay::Trigger::When::Enter || t.when == clouds::gameplay::Trigger::When::Exit)
      draw_volume(e, dl, t.volume, t.inside ? IM_COL32(255, 200, 60, 220) : IM_COL32(255, 160, 40, 140));
  });
  w.view<const clouds::weather::WeatherZone>().each([&](const clouds::weather::WeatherZone& z) {
    if (z.sphere) draw_sphere(e, dl, z.center, z.radius, IM_COL32(90, 200, 255, 140));
    else draw_box(e, dl, z.min, z.max, IM_COL32(90, 200, 255, 140));
  });
  w.view<const clouds::gameplay::LightningEvent>().each([&](const clouds::gameplay::LightningEvent& l) {
    ImVec2 s;
    if (world_to_screen(e, l.position, s)) {
      dl->AddCircle(s, 10.0f, IM_COL32(200, 220, 255, 255), 16, 2.0f);
      dl->AddText(ImVec2(s.x + 12.0f, s.y - 6.0f), IM_COL32(200, 220, 255, 255), "lightning");
    }
  });
}

}  // namespace cumulo::editor
