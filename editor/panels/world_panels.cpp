// Panels over the level's components: the weather scheduler and zones, the time of day, the cloudscapes.
#include <imgui.h>

#include <glm/gtc/quaternion.hpp>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "engine/app/simulation.h"
#include "engine/scene/components.h"
#include "engine/scene/sun.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::editor {
namespace {

std::string entity_name(const ecs::World& w, ecs::Entity e) {
  const auto* n = w.try_get<ecs::Name>(e);
  return n && !n->value.empty() ? n->value : "entity " + std::to_string(e.index);
}

std::string hours_text(const clouds::weather::ScheduleEntry& s) {
  if (s.from_hours <= 0.0f && s.to_hours >= 24.0f) return "all day";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%04.1f-%04.1f h", s.from_hours, s.to_hours);
  return buf;
}

void schedule_table(const char* id, const std::vector<clouds::weather::ScheduleEntry>& entries, float hours) {
  if (!ImGui::BeginTable(id, 3, ImGuiTableFlags_BordersInnerH | ImGuiTableFlags_SizingStretchProp)) return;
  for (const auto& s : entries) {
    const bool eligible = s.eligible_at(hours);
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    if (eligible) ImGui::TextUnformatted(s.state.c_str());
    else ImGui::TextDisabled("%s", s.state.c_str());
    ImGui::TableNextColumn();
    ImGui::Text("w %.2g", s.weight);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(hours_text(s).c_str());
  }
  ImGui::EndTable();
}

glm::vec3 viewer_position(const ecs::World& w) {
  if (const auto* v = w.try_resource<app::Viewer>())
    if (const auto* t = w.try_get<scene::Transform>(v->entity)) return t->position;
  return glm::vec3(0.0f);
}

}  // namespace

void draw_scheduler_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  ecs::World& w = e.world();
  const scene::ConstSunSource sun = scene::find_sun(static_cast<const ecs::World&>(w));
  const float hours = sun.time ? sun.time->hours : 12.0f;
  bool any = false;
  w.view<clouds::weather::WeatherScheduler>().each([&](ecs::Entity ent, clouds::weather::WeatherScheduler& s) {
    any = true;
    ImGui::PushID(int(ent.index));
    ImGui::Text("%s: %s", entity_name(w, ent).c_str(), s.current.c_str());
    if (!s.next.empty()) {
      ImGui::ProgressBar(s.t, ImVec2(-1.0f, 0.0f), ("-> " + s.next).c_str());
      item_tooltip("Transition progress: the talk's 10-30 s lerp between the two states.");
    } else {
      ImGui::TextDisabled("holding, next pick in %.0f s (%u transitions)", s.hold_left, s.transitions);
    }
    static int force = 0;
    const std::vector<std::string> ids = e.document().ids();
    if (!ids.empty()) {
      force = std::min(force, int(ids.size()) - 1);
      ImGui::SetNextItemWidth(150.0f);
      ImGui::Combo("##force", &force, [](void* d, int i, const char** out) {
        *out = (*static_cast<const std::vector<std::string>*>(d))[size_t(i)].c_str();
        return true;
      }, const_cast<std::vector<std::string>*>(&ids), int(ids.size()));
      ImGui::SameLine();
      if (ImGui::Button("Force transition")) {
        const std::string& id = ids[size_t(force)];
        if (const auto* lw = e.level_weather(); lw && lw->library && lw->library->find(id)) {
          clouds::weather::force_state(s, id);
          e.message(EditorMessage::Level::Info, "forced a transition to " + id);
        } else {
          e.message(EditorMessage::Level::Error, id + " is not in the running library");
        }
      }
    }
    const bool was = s.encounter_active;
    world_edit(e, ent, &clouds::weather::WeatherScheduler::encounter_active, was,
               ImGui::Checkbox("Encounter override", &s.encounter_active), "encounter override");
    item_tooltip("The boss fight's cycle replaces the regional one while on (the 2017 talk's encounter override).");
    ImGui::Text("Camera's zone: %s", s.zone.empty() ? "(none: the regional cycle)" : s.zone.c_str());
    if (ImGui::TreeNode("Schedule")) {
      schedule_table("schedule", s.schedule, hours);
      ImGui::TreePop();
    }
    if (!s.encounter.empty() && ImGui::TreeNode("Encounter")) {
      schedule_table("encounter", s.encounter, hours);
      ImGui::TreePop();
    }
    ImGui::PopID();
  });
  if (!any) ImGui::TextDisabled("The level has no WeatherScheduler.");
  const glm::vec3 viewer = viewer_position(w);
  w.view<const clouds::weather::WeatherZone>().each([&](ecs::Entity ent, const clouds::weather::WeatherZone& z) {
    ImGui::PushID(int(ent.index) + 100000);
    const bool inside = z.contains(viewer);
    const std::string title = "Zone " + (z.name.empty() ? entity_name(w, ent) : z.name) + (inside ? "  (camera inside)" : "");
    if (ImGui::TreeNode(title.c_str())) {
      ImGui::Text("priority %d, %s", z.priority, z.sphere ? "sphere" : "box");
      schedule_table("zone", z.states, hours);
      ImGui::TreePop();
    }
    ImGui::PopID();
  });
  ImGui::End();
}

void draw_time_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  scene::SunSource sun = scene::find_sun(e.world());
  if (!sun.time) {
    ImGui::TextDisabled("The level has no TimeOfDay.");
    return ImGui::End();
  }
  scene::TimeOfDay& t = *sun.time;
  // The time-of-day entity (the world resource, when the level has one, is not an entity: not undoable).
  ecs::Entity owner = ecs::Entity::null();
  e.world().view<const scene::TimeOfDay>().each([&](ecs::Entity ent, const scene::TimeOfDay& tod) {
    if (&tod == sun.time) owner = ent;
  });
  auto undoable = [&](float scene::TimeOfDay::*field, float before, bool changed, const char* label) {
    if (!owner.is_null()) world_edit(e, owner, field, before, changed, label);
  };
  float before = t.hours;
  undoable(&scene::TimeOfDay::hours, before, ImGui::SliderFloat("hours", &t.hours, 0.0f, 23.99f, "%.2f h"), "time of day");
  item_tooltip("Local solar time: moves the sun, the atmosphere and the clouds' light.");
  static float paused_speed = 0.0f;
  bool paused = t.hours_per_second == 0.0f && paused_speed != 0.0f;
  float speed = paused ? paused_speed : t.hours_per_second;
  before = t.hours_per_second;
  const bool speed_changed = ImGui::SliderFloat("speed", &speed, 0.0f, 0.5f, "%.4f h/s");
  if (speed_changed) {
    if (paused) paused_speed = speed;
    else t.hours_per_second = speed;
  }
  if (!paused) undoable(&scene::TimeOfDay::hours_per_second, before, speed_changed, "day speed");
  item_tooltip("Hours of the day per second of simulation (0: the sun stands still).");
  if (ImGui::Checkbox("pause", &paused)) {
    if (paused) {
      paused_speed = t.hours_per_second;
      t.hours_per_second = 0.0f;
    } else {
      t.hours_per_second = paused_speed;
      paused_speed = 0.0f;
    }
  }
  ImGui::End();
}

void draw_cloudscape_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  ecs::World& w = e.world();
  auto& opts = e.clouds().options();
  ImGui::SetNextItemWidth(140.0f);
  if (ImGui::BeginCombo("debug view", clouds::render::debug_view_name(opts.debug))) {
    for (const auto& row : clouds::render::kCloudDebugViewNames)
      if (ImGui::Selectable(row.name, row.value == opts.debug)) opts.debug = row.value;
    ImGui::EndCombo();
  }
  item_tooltip("The renderer's debug views: dimensional profile, SDF march steps per pixel, a light grid slice, the near/far split.");
  // The assets the level uses: any instance may take any of them (they share their GPU copy).
  std::vector<std::pair<std::string, std::filesystem::path>> assets;
  w.view<const clouds::Cloudscape>().each([&](const clouds::Cloudscape& c) {
    for (const auto& a : assets)
      if (a.first == c.asset) return;
    assets.emplace_back(c.asset, c.resolved);
  });
  w.view<clouds::Cloudscape, scene::Transform>().each([&](ecs::Entity ent, clouds::Cloudscape& c, scene::Transform& t) {
    ImGui::PushID(int(ent.index));
    if (ImGui::TreeNodeEx(entity_name(w, ent).c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::PushItemWidth(-90.0f);
      using scene::Transform;
      using clouds::Cloudscape;
      const glm::vec3 position = t.position;
      world_edit(e, ent, &Transform::position, position,
                 ImGui::DragFloat3("position", &t.position.x, 5.0f, -100000.0f, 100000.0f, "%.0f m"), "move cloudscape");
      item_tooltip("Drag to move the cloudscape (the 2023 talk's cloudscape transforms), or drag its handle in the viewport.");
      const glm::quat rotation = t.rotation;
      glm::vec3 euler = glm::degrees(glm::eulerAngles(t.rotation));
      const bool turned = ImGui::DragFloat3("rotation", &euler.x, 0.5f, -180.0f, 180.0f, "%.1f deg");
      if (turned) t.rotation = glm::quat(glm::radians(euler));
      world_edit(e, ent, &Transform::rotation, rotation, turned, "turn cloudscape");
      const glm::vec3 scale_before = t.scale;
      float scale = t.scale.x;
      const bool scaled = ImGui::DragFloat("scale", &scale, 0.01f, 0.05f, 20.0f, "%.2f");
      if (scaled) t.scale = glm::vec3(scale);
      world_edit(e, ent, &Transform::scale, scale_before, scaled, "scale cloudscape");
      item_tooltip("Uniform scale (the renderer takes uniform scales only).");
      float before = c.density;
      world_edit(e, ent, &Cloudscape::density, before, ImGui::SliderFloat("density", &c.density, 0.0f, 4.0f, "%.2f"),
                 "cloudscape density");
      item_tooltip("The instance's density multiplier (the weather state's voxel_density multiplies it).");
      before = c.dissipation;
      world_edit(e, ent, &Cloudscape::dissipation, before,
                 ImGui::SliderFloat("dissipation", &c.dissipation, 0.0f, 1.0f, "%.2f"), "cloudscape dissipation");
      before = c.rain;
      world_edit(e, ent, &Cloudscape::rain, before, ImGui::SliderFloat("rain", &c.rain, 0.0f, 1.0f, "%.2f"), "cloudscape rain");
      if (assets.size() > 1 && ImGui::BeginCombo("asset", c.asset.c_str())) {
        for (const auto& [name, resolved] : assets)
          if (ImGui::Selectable(name.c_str(), name == c.asset) && name != c.asset) {
            const std::string old_asset = c.asset;
            const std::filesystem::path old_resolved = c.resolved;
            c.asset = name;
            c.resolved = resolved;
            auto set = [ent](std::string a, std::filesystem::path r) {
              return [ent, a, r](ecs::World& w) {
                if (auto* cs = w.try_get<Cloudscape>(ent)) cs->asset = a, cs->resolved = r;
              };
            };
            e.push_world_edit("cloudscape asset", set(old_asset, old_resolved), set(name, resolved));
          }
        ImGui::EndCombo();
      }
      ImGui::PopItemWidth();
      ImGui::TreePop();
    }
    ImGui::PopID();
  });
  ImGui::End();
}

}  // namespace cumulo::editor
