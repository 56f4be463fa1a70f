#include "editor/editor.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <set>

#include "editor/model/edit_serial.h"
#include "editor/panels/panels.h"
#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/platform/window.h"
#include "engine/render/frame_renderer.h"
#include "modules/clouds/gameplay/triggers.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/render/sky_layer.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"

namespace cumulo::editor {
namespace {

// The renderer's own map generator: what the sky layer draws for a source is what painting starts from.
PaintedCloudMap render_map(const clouds::weather::CloudMapSource& source) {
  clouds::render::CloudMapImage m = clouds::render::make_cloud_map(source);
  PaintedCloudMap out;
  out.width = m.width;
  out.height = m.height;
  out.rgba = std::move(m.rgba);
  return out;
}

constexpr std::chrono::milliseconds kDiskPollPeriod{500};
constexpr size_t kFramePlotSamples = 240;
constexpr size_t kMessagesKept = 200;

ImVec4 message_colour(EditorMessage::Level level) {
  return level == EditorMessage::Level::Error     ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f)
         : level == EditorMessage::Level::Warning ? ImVec4(1.0f, 0.8f, 0.3f, 1.0f)
                                                  : ImVec4(0.8f, 0.85f, 0.9f, 1.0f);
}

}  // namespace

Editor::Editor(clouds::render::CloudFeature& clouds, const std::filesystem::path& weather_folder)
    : clouds_(clouds),
      doc_(std::make_unique<WeatherDocument>(WeatherDocument::open(weather_folder, render_map))),
      watch_(std::make_unique<FolderWatch>(weather_folder, kDiskPollPeriod)) {
  for (const std::string& p : doc_->problems()) message(EditorMessage::Level::Error, p);
  message(EditorMessage::Level::Info, strf("editing %zu weather states in %s", doc_->ids().size(),
                                           weather_folder.string().c_str()));
}

void Editor::message(EditorMessage::Level level, const std::string& text) {
  messages_.push_back({level, text, time_s_});
  while (messages_.size() > kMessagesKept) messages_.pop_front();
  if (level == EditorMessage::Level::Error) LOG_ERROR("editor: %s", text.c_str());
  else if (level == EditorMessage::Level::Warning) LOG_WARN("editor: %s", text.c_str());
  else LOG_INFO("editor: %s", text.c_str());
}

void Editor::set_camera(const scene::CameraView& view, uint32_t width, uint32_t height, double sim_time_s) {
  camera = view;
  sim_time = sim_time_s;
  view_width = width;
  view_height = height;
}

std::string Editor::target_state() const {
  if (!selected.empty() && doc_->has(selected)) return selected;
  std::string current;
  if (world_)
    static_cast<const ecs::World&>(*world_).view<const clouds::weather::WeatherScheduler>().each(
        [&](const clouds::weather::WeatherScheduler& s) {
          if (current.empty()) current = s.current;
        });
  if (!current.empty() && doc_->has(current)) return current;
  if (const auto* lw = level_weather(); lw && lw->start && doc_->has(lw->start->id)) return lw->start->id;
  const auto ids = doc_->ids();
  return ids.empty() ? std::string() : ids.front();
}

std::vector<std::string> Editor::states_in_use() const {
  std::set<std::string> used;
  if (!world_) return {};
  const ecs::World& w = *world_;
  w.view<const clouds::weather::WeatherScheduler>().each([&](const clouds::weather::WeatherScheduler& s) {
    used.insert(s.start);
    used.insert(s.current);
    if (!s.next.empty()) used.insert(s.next);
    for (const auto& e : s.schedule) used.insert(e.state);
    for (const auto& e : s.encounter) used.insert(e.state);
  });
  w.view<const clouds::weather::WeatherZone>().each([&](const clouds::weather::WeatherZone& z) {
    for (const auto& e : z.states) used.insert(e.state);
  });
  w.view<const clouds::gameplay::Trigger>().each([&](const clouds::gameplay::Trigger& t) {
    for (const std::string& s : clouds::gameplay::trigger_weather_states(t)) used.insert(s);
  });
  if (const auto* lw = level_weather(); lw && lw->start) used.insert(lw->start->id);
  used.erase("");
  return {used.begin(), used.end()};
}

void Editor::sync_live() {
  // Serials only grow: a top step newer than any seen is a new document edit (a redo brings back an older one).
  if (doc_->undo_serial() > newest_doc_serial_) {
    world_redo_.clear();
    newest_doc_serial_ = doc_->undo_serial();
  }
  clouds::weather::LevelWeather* lw = level_weather();
  clouds::weather::WeatherLibrary* lib = lw && lw->library ? &*lw->library : nullptr;
  for (const std::string& id : doc_->take_changed()) {
    if (doc_->has(id)) {
      const clouds::weather::WeatherState s = doc_->state(id);
      if (lib) lib->put(s);
      if (lw && lw->start && lw->start->id == id) lw->start = s;
    } else if (lib) {
      // The level's states are never removed under it (the panels refuse); a removed editor-made one goes.
      const auto used = states_in_use();
      if (std::find(used.begin(), used.end(), id) == used.end()) lib->erase(id);
    }
  }
  update_preview();
}

void Editor::update_preview() {
  clouds::weather::LevelWeather* lw = level_weather();
  if (!lw) return;
  if (!pin_selected || selected.empty() || !doc_->has(selected)) {
    lw->preview.reset();
    return;
  }
  clouds::weather::WeatherState s = doc_->state(selected);
  if (blend_to && doc_->has(*blend_to)) s = clouds::weather::blend(s, doc_->state(*blend_to), blend_t).state;
  lw->preview = std::move(s);
}

bool Editor::set_param(const std::string& id, const std::string& param, const Json& value, bool merge) {
  try {
    doc_->set(id, param, value, merge);
  } catch (const Error& e) {
    message(EditorMessage::Level::Error, e.what());
    return false;
  }
  sync_live();
  return true;
}

bool Editor::paint(const std::string& id, glm::vec2 uv, bool stroke_start, bool stroke_end) {
  try {
    if (stroke_start) doc_->begin_stroke(id);
    doc_->paint(id, brush_channel, uv, brush_radius, brush_value, brush_strength);
    if (stroke_end) doc_->end_stroke();
  } catch (const Error& e) {
    message(EditorMessage::Level::Error, e.what());
    return false;
  }
  sync_live();
  return true;
}

bool Editor::undo() {
  // An open paint stroke is the newest edit of all.
  const uint64_t doc = doc_->in_stroke() ? UINT64_MAX : doc_->undo_serial();
  const uint64_t world = world_undo_.empty() ? 0 : world_undo_.back().serial;
  if (doc == 0 && world == 0) return false;
  std::string label;
  if (doc > world) {
    label = doc_->undo_label();
    doc_->undo();
    if (label.empty()) label = doc_->redo_label();
    sync_live();
  } else {
    WorldEdit e = std::move(world_undo_.back());
    world_undo_.pop_back();
    e.undo(*world_);
    label = e.label;
    world_redo_.push_back(std::move(e));
  }
  message(EditorMessage::Level::Info, "undo: " + label);
  return true;
}

bool Editor::redo() {
  // The most recently undone comes back first: the older of the two tops.
  const uint64_t doc = doc_->redo_serial();
  const uint64_t world = world_redo_.empty() ? 0 : world_redo_.back().serial;
  if (doc == 0 && world == 0) return false;
  std::string label;
  if (doc != 0 && (world == 0 || doc < world)) {
    label = doc_->redo_label();
    doc_->redo();
    sync_live();
  } else {
    WorldEdit e = std::move(world_redo_.back());
    world_redo_.pop_back();
    e.redo(*world_);
    label = e.label;
    world_undo_.push_back(std::move(e));
  }
  message(EditorMessage::Level::Info, "redo: " + label);
  return true;
}

void Editor::push_world_edit(std::string label, std::function<void(ecs::World&)> undo,
                             std::function<void(ecs::World&)> redo) {
  world_undo_.push_back({std::move(label), std::move(undo), std::move(redo), next_edit_serial()});
  if (world_undo_.size() > 512) world_undo_.erase(world_undo_.begin());
  world_redo_.clear();
  doc_->clear_redo();
}

bool Editor::save() {
  try {
    doc_->save();
  } catch (const Error& e) {
    message(EditorMessage::Level::Error, std::string("save failed, nothing was lost: ") + e.what());
    return false;
  }
  sync_live();  // a painted map is now the PNG beside its state
  message(EditorMessage::Level::Info, "saved " + doc_->folder().string());
  return true;
}

void Editor::poll_disk() {
  std::vector<DiskEvent> events;
  try {
    events = doc_->poll_disk();
  } catch (const Error& e) {
    message(EditorMessage::Level::Error, e.what());
    return;
  }
  for (const DiskEvent& e : events) {
    switch (e.kind) {
      case DiskEvent::Kind::Reloaded: message(EditorMessage::Level::Info, "reloaded " + e.id + " (changed on disk)"); break;
      case DiskEvent::Kind::Added: message(EditorMessage::Level::Info, "new state on disk: " + e.id); break;
      case DiskEvent::Kind::Removed: message(EditorMessage::Level::Warning, "removed on disk: " + e.id); break;
      case DiskEvent::Kind::Malformed:
        message(EditorMessage::Level::Error, e.message + " (the last good " + e.id + " keeps running)");
        break;
      case DiskEvent::Kind::Conflict:
        if (std::find(conflicts_.begin(), conflicts_.end(), e.id) == conflicts_.end()) conflicts_.push_back(e.id);
        message(EditorMessage::Level::Warning, e.id + " changed on disk while edited here");
        break;
    }
  }
  if (!events.empty()) sync_live();
}

void Editor::hotkeys(const std::vector<std::pair<int, int>>& presses) {
  if (ImGui::GetIO().WantTextInput) return;  // a text field has its own undo
  for (const auto& [key, mods] : presses) {
    if (!(mods & GLFW_MOD_CONTROL)) continue;
    if (key == GLFW_KEY_Z && (mods & GLFW_MOD_SHIFT)) redo();
    else if (key == GLFW_KEY_Z) undo();
    else if (key == GLFW_KEY_Y) redo();
    else if (key == GLFW_KEY_S) save();
  }
}

bool Editor::allow_close() {
  if (quit_confirmed_ || !doc_->dirty()) return true;
  quit_prompt_ = true;
  return false;
}

void Editor::draw_quit_prompt() {
  if (quit_prompt_) {
    ImGui::OpenPopup("Unsaved changes");
    quit_prompt_ = false;
  }
  ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Weather states have unsaved changes:");
    for (const std::string& id : doc_->ids())
      if (doc_->dirty(id)) ImGui::BulletText("%s", id.c_str());
    if (ImGui::Button("Save and quit")) {
      if (save()) {
        quit_confirmed_ = true;
        window_->window.request_close();
      }
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Quit without saving")) {
      quit_confirmed_ = true;
      window_->window.request_close();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
}

void Editor::draw_conflicts() {
  if (conflicts_.empty()) return;
  ImGui::SetNextWindowPos(ImVec2(ImGui::GetMainViewport()->GetCenter().x, 40.0f), ImGuiCond_Appearing, ImVec2(0.5f, 0.0f));
  ImGui::Begin("Changed on disk", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  for (size_t i = 0; i < conflicts_.size();) {
    const std::string id = conflicts_[i];
    ImGui::PushID(id.c_str());
    ImGui::Text("%s changed on disk while you edited it.", id.c_str());
    bool done = false;
    if (ImGui::Button("Take the file on disk")) {
      try {
        doc_->resolve_conflict(id, true);
      } catch (const Error& e) {
        message(EditorMessage::Level::Error, e.what());
      }
      done = true;
    }
    ImGui::SameLine();
    if (ImGui::Button("Keep mine (saving overwrites it)")) {
      doc_->resolve_conflict(id, false);
      done = true;
    }
    ImGui::PopID();
    if (done) {
      conflicts_.erase(conflicts_.begin() + long(i));
      sync_live();
    } else {
      ++i;
    }
  }
  ImGui::End();
}

void Editor::draw_menu_bar() {
  if (!ImGui::BeginMainMenuBar()) return;
  if (ImGui::BeginMenu("File")) {
    if (ImGui::MenuItem("Save", "Ctrl+S", false, doc_->dirty())) save();
    if (ImGui::MenuItem("Quit", "Esc")) window_->window.request_close();
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("Edit")) {
    const bool can_undo = doc_->can_undo() || !world_undo_.empty();
    const bool can_redo = doc_->can_redo() || !world_redo_.empty();
    if (ImGui::MenuItem("Undo", "Ctrl+Z", false, can_undo)) undo();
    if (ImGui::MenuItem("Redo", "Ctrl+Shift+Z", false, can_redo)) redo();
    ImGui::EndMenu();
  }
  if (ImGui::BeginMenu("View")) {
    for (PanelInfo& p : panels()) ImGui::MenuItem(p.title, nullptr, &p.open);
    ImGui::MenuItem("Overlay in the viewport", nullptr, &show_overlay);
    ImGui::MenuItem("Messages", nullptr, &show_messages_);
    ImGui::EndMenu();
  }
  ImGui::TextDisabled("|  %s%s", doc_->folder().filename().string().c_str(), doc_->dirty() ? "  (unsaved changes)" : "");
  ImGui::EndMainMenuBar();
}

void Editor::draw_shader_errors() {
  // Hot reload keeps the last good pipeline of a shader that fails to compile; say which and why here,
  // where the person editing it is looking.
  const std::string errors = window_->renderer.shader_errors();
  if (errors != last_shader_errors_) {
    if (!errors.empty()) message(EditorMessage::Level::Error, "shader hot reload failed; the old pipeline keeps running");
    else if (!last_shader_errors_.empty()) message(EditorMessage::Level::Info, "shaders reloaded");
    last_shader_errors_ = errors;
  }
  if (errors.empty()) return;
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->GetCenter().x, vp->Pos.y + 30.0f), ImGuiCond_Appearing, ImVec2(0.5f, 0.0f));
  ImGui::SetNextWindowSize(ImVec2(vp->Size.x * 0.5f, 0.0f), ImGuiCond_Appearing);
  ImGui::Begin("Shader errors (the old pipeline keeps running)");
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.5f, 0.45f, 1.0f));
  ImGui::TextWrapped("%s", errors.c_str());
  ImGui::PopStyleColor();
  ImGui::End();
}

void Editor::draw_status() {
  if (show_messages_) {
    ImGui::SetNextWindowSize(ImVec2(520.0f, 220.0f), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Messages", &show_messages_)) {
      for (const EditorMessage& m : messages_) {
        ImGui::TextColored(message_colour(m.level), "%7.1f s  %s", m.time_s, m.text.c_str());
      }
      if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);  // follow the newest
    }
    ImGui::End();
  }
  if (messages_.empty()) return;
  const EditorMessage& m = messages_.back();
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(vp->Pos.x, vp->Pos.y + vp->Size.y), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
  ImGui::SetNextWindowSize(ImVec2(vp->Size.x, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::Begin("##status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
  ImGui::TextColored(message_colour(m.level), "%s", m.text.c_str());
  ImGui::End();
}

void Editor::frame(ecs::World& world, app::WindowServices& window, double dt_s,
                   const std::vector<std::pair<int, int>>& shortcuts) {
  world_ = &world;
  window_ = &window;
  time_s_ += dt_s;
  frame_ms.push_back(float(dt_s * 1000.0));
  while (frame_ms.size() > kFramePlotSamples) frame_ms.pop_front();
  if (watch_->changed()) poll_disk();
  run_script_step();
  hotkeys(shortcuts);

  draw_menu_bar();
  for (PanelInfo& p : panels()) {
    if (!p.open) continue;
    try {
      p.draw(*this, p);
    } catch (const std::exception& e) {
      // A panel that fails says so and closes its windows; the editor and the others go on.
      ImGui::ErrorCheckEndFrameRecover(nullptr);
      message(EditorMessage::Level::Error, std::string(p.title) + ": " + e.what());
    }
  }
  if (show_overlay) {
    draw_viewport_overlay(*this);
    draw_cloudscape_handles(*this);
  }
  draw_shader_errors();
  draw_conflicts();
  draw_quit_prompt();
  draw_status();
  update_preview();
}

}  // namespace cumulo::editor
