// The weather states panel: the list (create, duplicate, rename, delete), every parameter of the state
// being edited with its range and tooltip from the parameter table, and the blend preview.
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>

#include "editor/editor.h"
#include "editor/model/weather_params.h"
#include "editor/panels/panels.h"
#include "engine/core/error.h"

namespace cumulo::editor {
namespace {

// The name popup shared by New, Duplicate and Rename.
struct NamePrompt {
  enum class Kind { None, Create, Duplicate, Rename } kind = Kind::None;
  std::string name, source;
  bool open_now = false;
};

void prompt_name(Editor& e, NamePrompt& prompt) {
  if (prompt.open_now) {
    ImGui::OpenPopup("State name");
    prompt.open_now = false;
  }
  if (!ImGui::BeginPopup("State name")) return;
  const char* what = prompt.kind == NamePrompt::Kind::Create      ? "New state from"
                     : prompt.kind == NamePrompt::Kind::Duplicate ? "Duplicate of"
                                                                  : "Rename";
  ImGui::Text("%s %s", what, prompt.source.c_str());
  if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
  const bool enter = ImGui::InputText("name", &prompt.name, ImGuiInputTextFlags_EnterReturnsTrue);
  item_tooltip("Letters, digits, _ and -: the file name of the state (NAME.json).");
  if (enter || ImGui::Button("OK")) {
    try {
      WeatherDocument& doc = e.document();
      if (prompt.kind == NamePrompt::Kind::Create) doc.create(prompt.name, prompt.source);
      else if (prompt.kind == NamePrompt::Kind::Duplicate) doc.duplicate(prompt.source, prompt.name);
      else doc.rename(prompt.source, prompt.name);
      e.selected = prompt.name;
      e.sync_live();
      ImGui::CloseCurrentPopup();
    } catch (const Error& err) {
      e.message(EditorMessage::Level::Error, err.what());
    }
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
  ImGui::EndPopup();
}

void state_list(Editor& e, NamePrompt& prompt) {
  WeatherDocument& doc = e.document();
  const std::vector<std::string> used = e.states_in_use();
  const std::string target = e.target_state();
  if (ImGui::BeginListBox("##states", ImVec2(-1.0f, 5.5f * ImGui::GetTextLineHeightWithSpacing()))) {
    for (const std::string& id : doc.ids()) {
      const bool in_use = std::find(used.begin(), used.end(), id) != used.end();
      const std::string label = id + (doc.dirty(id) ? " *" : "") + (in_use ? "  (level)" : "");
      if (ImGui::Selectable(label.c_str(), id == target)) e.selected = id;
    }
    ImGui::EndListBox();
  }
  const bool in_use = std::find(used.begin(), used.end(), target) != used.end();
  if (ImGui::Button("New")) prompt = {NamePrompt::Kind::Create, "new_state", target, true};
  item_tooltip("A new state with the selected state's parameters (no painted map).");
  ImGui::SameLine();
  if (ImGui::Button("Duplicate")) prompt = {NamePrompt::Kind::Duplicate, target + "_copy", target, true};
  ImGui::SameLine();
  ImGui::BeginDisabled(in_use);
  if (ImGui::Button("Rename")) prompt = {NamePrompt::Kind::Rename, target, target, true};
  ImGui::SameLine();
  if (ImGui::Button("Delete")) {
    try {
      doc.remove(target);
      e.selected.clear();
      e.sync_live();
    } catch (const Error& err) {
      e.message(EditorMessage::Level::Error, err.what());
    }
  }
  ImGui::EndDisabled();
  if (in_use) item_tooltip("The level's scheduler, zones or triggers name this state: it cannot be renamed or deleted here.");
  prompt_name(e, prompt);
}

void blend_preview(Editor& e) {
  ImGui::Checkbox("Show the selected state", &e.pin_selected);
  item_tooltip("Draw the selected state in the viewport instead of the scheduler's weather (the simulation goes on).");
  if (!e.pin_selected || e.selected.empty()) return;
  const std::string preview = e.blend_to ? *e.blend_to : std::string("(no blend)");
  ImGui::SetNextItemWidth(140.0f);
  if (ImGui::BeginCombo("blend to", preview.c_str())) {
    if (ImGui::Selectable("(no blend)", !e.blend_to)) e.blend_to.reset();
    for (const std::string& id : e.document().ids())
      if (ImGui::Selectable(id.c_str(), e.blend_to && *e.blend_to == id)) e.blend_to = id;
    ImGui::EndCombo();
  }
  item_tooltip("Preview the scheduler's transition: the two states lerped parameter by parameter.");
  if (e.blend_to) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    ImGui::SliderFloat("##t", &e.blend_t, 0.0f, 1.0f, "t %.2f");
  }
}

// One widget for one parameter; changes go through the document (validated, undoable, live).
void param_widget(Editor& e, const std::string& id, const Json& state, const ParamInfo& p) {
  Json value;
  try {
    value = get_param(state, p.path);
  } catch (const Error&) {
    if (p.default_value.is_null()) {
      ImGui::TextDisabled("%s: (absent)", p.label.c_str());
      return;
    }
    value = p.default_value;  // an optional key the state leaves out: its default, written once edited
  }
  bool changed = false;
  Json out;
  ImGui::PushID(p.path.c_str());
  switch (p.kind) {
    case ParamKind::Float: {
      float v = value.is_number() ? value.get<float>() : 0.0f;
      // Wide ranges (absorption 1e-5..10, wind 0..200 m/s) on a logarithmic slider: the useful values are small.
      const bool wide = p.max - p.min > 20.0;
      const ImGuiSliderFlags flags =
          wide ? ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoRoundToFormat : ImGuiSliderFlags_None;
      changed = ImGui::SliderFloat(p.label.c_str(), &v, float(p.min), float(p.max), wide ? "%.4g" : "%.3f", flags);
      out = v;
      break;
    }
    case ParamKind::Int: {
      int v = value.is_number() ? value.get<int>() : 0;
      changed = ImGui::DragInt(p.label.c_str(), &v, 1.0f, int(p.min), int(std::min(p.max, 2147483647.0)));
      out = v;
      break;
    }
    case ParamKind::Vec3: {
      float v[3] = {0, 0, 0};
      if (value.is_array() && value.size() == 3)
        for (int i = 0; i < 3; ++i) v[i] = value[size_t(i)].is_number() ? value[size_t(i)].get<float>() : 0.0f;
      changed = ImGui::DragFloat3(p.label.c_str(), v, 0.01f, float(p.min), float(p.max), "%.2f");
      out = Json::array({v[0], v[1], v[2]});
      break;
    }
    case ParamKind::Text: {
      // The text being typed lives here until the field is left (one field is active at a time); it is
      // one edit when committed, not one per key.
      static std::string buffer, active_key;
      const std::string key = id + "\n" + p.path;
      std::string current = value.is_string() ? value.get<std::string>() : std::string();
      std::string* text = active_key == key ? &buffer : &current;
      ImGui::InputText(p.label.c_str(), text);
      if (ImGui::IsItemActivated()) {
        buffer = *text;
        active_key = key;
      }
      if (ImGui::IsItemDeactivated()) {
        changed = ImGui::IsItemDeactivatedAfterEdit();
        out = buffer;
        active_key.clear();
      }
      break;
    }
  }
  item_tooltip(p.tooltip.c_str());
  // A drag is one undo step: the first change of an activation starts it, the rest merge into it.
  if (changed) e.set_param(id, p.path, out, /*merge=*/!ImGui::IsItemActivated() && p.kind != ParamKind::Text);
  ImGui::PopID();
}

}  // namespace

void draw_weather_panel(Editor& e, PanelInfo& panel) {
  static NamePrompt prompt;
  if (!begin_panel(panel)) return ImGui::End();
  state_list(e, prompt);
  blend_preview(e);
  ImGui::Separator();
  const std::string id = e.target_state();
  if (id.empty()) {
    ImGui::TextDisabled("No weather state to edit.");
    return ImGui::End();
  }
  ImGui::Text("Editing %s%s", id.c_str(), e.document().dirty(id) ? " (unsaved)" : "");
  if (e.selected.empty()) item_tooltip("The scheduler's current state; select one in the list to pin it.");
  const Json& state = e.document().json(id);
  ImGui::PushItemWidth(-120.0f);
  for (const std::string& group : weather_param_groups()) {
    if (!ImGui::CollapsingHeader(group.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) continue;
    for (const ParamInfo& p : weather_params())
      if (p.group == group) param_widget(e, id, state, p);
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace cumulo::editor
