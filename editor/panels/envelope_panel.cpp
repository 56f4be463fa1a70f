// The Envelope method's orographic clouds (issue 24): each OrographicClouds component's density, coverage, edge and
// wind, and its rules' heights, coverage, detail and roughness. The renderer bakes the maps again once a changed value
// rests (envelope_pass.cpp), so a dragged slider shows the last baked clouds until it is let go.
#include <imgui.h>

#include <cstdio>
#include <string>
#include <variant>

#include "editor/editor.h"
#include "editor/panels/panels.h"
#include "modules/clouds/envelope/orographic_clouds.h"

namespace cumulo::editor {
namespace {

using clouds::envelope::BankRule;
using clouds::envelope::CapRule;
using clouds::envelope::EnvelopeRule;
using clouds::envelope::LayerRule;
using clouds::envelope::OrographicClouds;

std::string envelope_name(const ecs::World& w, ecs::Entity e) {
  const auto* n = w.try_get<ecs::Name>(e);
  return n && !n->value.empty() ? n->value : "entity " + std::to_string(e.index);
}

// One undo step per change of the whole component: the rules live in a vector, which world_edit's member pointers do
// not reach. A drag is one step, from its activation to its release.
class ComponentEdit {
 public:
  ComponentEdit(Editor& e, ecs::Entity entity, const OrographicClouds& before) : e_(e), entity_(entity), before_(before) {}
  void after(bool changed, const char* label) {
    const ImGuiID id = ImGui::GetItemID();
    auto restore = [entity = entity_](OrographicClouds value) {
      return [entity, value](ecs::World& w) {
        if (auto* c = w.try_get<OrographicClouds>(entity)) *c = value;
      };
    };
    if (ImGui::IsItemActivated()) e_.world_drag = {{id, restore(before_)}};
    const auto* now = static_cast<const ecs::World&>(e_.world()).try_get<OrographicClouds>(entity_);
    if (!now) return;
    if (ImGui::IsItemDeactivatedAfterEdit() && e_.world_drag && e_.world_drag->first == id) {
      e_.push_world_edit(label, e_.world_drag->second, restore(*now));
      e_.world_drag.reset();
    } else if (changed && !ImGui::IsItemActive()) {
      e_.push_world_edit(label, restore(before_), restore(*now));
    }
    before_ = *now;
  }

 private:
  Editor& e_;
  ecs::Entity entity_;
  OrographicClouds before_;
};

void rule_widgets(EnvelopeRule& r, ComponentEdit& edit) {
  if (auto* cap = std::get_if<CapRule>(&r.kind)) {
    edit.after(ImGui::DragFloat("radius", &cap->radius_m, 2.0f, 10.0f, 20000.0f, "%.0f m"), "cap radius");
    edit.after(ImGui::DragFloat("base", &cap->base_m, 1.0f, -1000.0f, 20000.0f, "%.0f m"), "cap base");
    edit.after(ImGui::DragFloat("top", &cap->top_m, 1.0f, -1000.0f, 20000.0f, "%.0f m"), "cap top");
    item_tooltip("Heights above sea level; the top comes down to 60 % of the thickness at the radius (a dome).");
  } else if (auto* bank = std::get_if<BankRule>(&r.kind)) {
    edit.after(ImGui::DragFloat2("terrain band", &bank->terrain_m.x, 1.0f, -1000.0f, 20000.0f, "%.0f m"), "bank band");
    item_tooltip("The ground heights the bank lies over (fading over a quarter of the band at both ends).");
    edit.after(ImGui::DragFloat("base above ground", &bank->base_above_terrain_m, 1.0f, 0.0f, 5000.0f, "%.0f m"), "bank base");
    edit.after(ImGui::DragFloat("thickness", &bank->thickness_m, 1.0f, 10.0f, 5000.0f, "%.0f m"), "bank thickness");
  } else if (auto* layer = std::get_if<LayerRule>(&r.kind)) {
    edit.after(ImGui::DragFloat("top", &layer->top_m, 1.0f, -1000.0f, 20000.0f, "%.0f m"), "layer top");
    edit.after(ImGui::DragFloat("below terrain", &layer->below_terrain_m, 1.0f, -1000.0f, 20000.0f, "%.0f m"),
               "layer extent");
    item_tooltip("Valley or sea fog: where the terrain lies below this height.");
  }
  edit.after(ImGui::SliderFloat("coverage", &r.coverage, 0.0f, 1.0f, "%.2f"), "rule coverage");
  edit.after(ImGui::SliderFloat("detail type", &r.detail_type, 0.0f, 1.0f, "%.2f"), "rule detail type");
  item_tooltip("0 wispy .. 1 billowy (the noise composite the up-rez erodes).");
  edit.after(ImGui::SliderFloat("variation", &r.variation, 0.0f, 1.0f, "%.2f"), "rule variation");
  edit.after(ImGui::DragFloat("variation size", &r.variation_m, 1.0f, 1.0f, 100000.0f, "%.0f m"), "rule variation size");
  item_tooltip("The top's and the coverage's roughness: a 2D fBm of features this size lifts and lowers the top.");
}

}  // namespace

void draw_envelope_panel(Editor& e, PanelInfo& panel) {
  if (!begin_panel(panel)) return ImGui::End();
  ecs::World& w = e.world();
  bool any = false;
  w.view<OrographicClouds>().each([&](ecs::Entity ent, OrographicClouds& c) {
    any = true;
    ImGui::PushID(int(ent.index));
    if (ImGui::TreeNodeEx(envelope_name(w, ent).c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::PushItemWidth(-120.0f);
      ComponentEdit edit(e, ent, c);
      const glm::vec2 size = c.extent_max - c.extent_min;
      ImGui::TextDisabled("%.0f x %.0f m at %u texels, %zu rules%s", size.x, size.y, c.resolution, c.rules.size(),
                          c.maps ? ", painted maps" : "");
      edit.after(ImGui::SliderFloat("density", &c.density, 0.0f, 4.0f, "%.2f"), "envelope density");
      item_tooltip("Density multiplier (the weather state's envelope.density multiplies it).");
      edit.after(ImGui::SliderFloat("coverage", &c.coverage, 0.0f, 1.0f, "%.2f"), "envelope coverage");
      item_tooltip("Multiplies every rule's coverage (the weather state's envelope.coverage multiplies it again).");
      edit.after(ImGui::DragFloat("edge", &c.edge_m, 0.5f, 0.1f, 10000.0f, "%.1f m"), "envelope edge");
      item_tooltip("The edge gradient's width: the profile rises from 0 at the footprint's side to 1 this far in (the talk's 35).");
      edit.after(ImGui::DragFloat("wind speed", &c.wind_speed, 0.1f, 0.0f, 200.0f, "%.1f m/s"), "envelope wind");
      for (size_t i = 0; i < c.rules.size(); ++i) {
        ImGui::PushID(int(i));
        char label[64];
        std::snprintf(label, sizeof label, "%zu: %s", i,
                      clouds::envelope::kRuleTypeNames[size_t(c.rules[i].type())].name);
        if (ImGui::TreeNode(label)) {
          rule_widgets(c.rules[i], edit);
          ImGui::TreePop();
        }
        ImGui::PopID();
      }
      ImGui::PopItemWidth();
      ImGui::TreePop();
    }
    ImGui::PopID();
  });
  if (!any) ImGui::TextDisabled("The level has no OrographicClouds.");
  ImGui::End();
}

}  // namespace cumulo::editor
