#pragma once
// The weather editor (`cumulo edit`, issue 12): Dear ImGui panels over the running level, one per
// component (Unity's inspector, Unreal's details panel, Wicked Engine's weather window), editing the
// weather JSON of content/weather/ through a WeatherDocument (editor/model: undo/redo, atomic saving,
// painting, disk watching) and mirroring every change into the live engine within the frame.
//
// [SECTION] index
//   Editor                 the state the panels share, the live sync, hotkeys, the quit prompt, scripts
//   panels/*.cpp           draw_weather_panel, draw_scheduler_panel, draw_time_panel, draw_cloudscape_panel,
//                          draw_paint_panel, draw_events_panel (+ the viewport overlay), draw_performance_panel
//
// Every panel is a free function over Editor& (panels.h); the module (editor_module.h) owns the Editor
// from the window's opening to its closing and calls frame() between ImGui's NewFrame and Render.
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "editor/model/editor_script.h"
#include "editor/model/folder_watch.h"
#include "editor/model/weather_document.h"
#include "engine/app/module.h"
#include "engine/ecs/world.h"
#include "engine/scene/camera.h"
#include "modules/clouds/weather/level_weather.h"

namespace cumulo::clouds::render {
class CloudFeature;
}

namespace cumulo::editor {

// One line of the editor's message log (the last in the status bar, all in View > Messages).
struct EditorMessage {
  enum class Level { Info, Warning, Error } level = Level::Info;
  std::string text;
  double time_s = 0.0;
};

class Editor {
 public:
  Editor(clouds::render::CloudFeature& clouds, const std::filesystem::path& weather_folder);

  // Every frame, between ImGui::NewFrame and ImGui::Render: disk watch, script step, hotkeys, panels.
  // `shortcuts`: (GLFW key, mods) pressed since the last frame.
  void frame(ecs::World& world, app::WindowServices& window, double dt_s,
             const std::vector<std::pair<int, int>>& shortcuts = {});
  // The window was asked to close: true to let it (saved, or the person chose to discard).
  bool allow_close();
  void set_script(std::vector<ScriptAction> actions, std::filesystem::path file);
  // The script's error (empty: none or still running); `cumulo edit` exits non-zero with it.
  const std::string& script_error() const { return script_error_; }
  // The camera of the last extracted frame (the overlay's projection, "the camera's target").
  void set_camera(const scene::CameraView& view, uint32_t width, uint32_t height, double sim_time_s);
  // A screenshot the script asked for: the module reads the next presented frame back into it.
  std::optional<std::filesystem::path> take_screenshot_request();
  void screenshot_written(const std::filesystem::path& path, const std::string& error);

  // ---- shared with the panels (panels.h) ----
  WeatherDocument& document() { return *doc_; }
  clouds::render::CloudFeature& clouds() { return clouds_; }
  ecs::World& world() { return *world_; }
  // The level's weather in the world (null before the first frame).
  clouds::weather::LevelWeather* level_weather() const {
    return world_ ? world_->try_resource<clouds::weather::LevelWeather>() : nullptr;
  }
  app::WindowServices& window() { return *window_; }
  // The state the weather panel edits: the selected one, else the scheduler's current state.
  std::string target_state() const;
  std::string selected;                 // "" until the person (or a script) selects one
  bool pin_selected = true;             // draw the selected state instead of the scheduler's weather
  std::optional<std::string> blend_to;  // preview a blend selected -> blend_to at blend_t
  float blend_t = 0.5f;
  // The painting brush.
  MapChannel brush_channel = MapChannel::Coverage;
  float brush_radius = 0.05f, brush_strength = 0.8f, brush_value = 0.0f;
  bool show_overlay = true;
  scene::CameraView camera;
  uint32_t view_width = 0, view_height = 0;
  double sim_time = 0.0;       // of the last extracted frame (the cloud map's wind drift)
  float target_distance = 1500.0f;  // "the camera's target": this far along the view
  std::deque<float> frame_ms;  // the frame-time plot (most recent last)
  double ui_cpu_ms = 0.0;      // this editor's own CPU time in the last frame (panels + sync)
  double ui_cpu_ms_max = 0.0;

  // Edits through the document, then pushed live; a refused edit becomes an error message (and, in a
  // script, stops it). Return false when refused.
  bool set_param(const std::string& id, const std::string& param, const Json& value, bool merge = false);
  bool paint(const std::string& id, glm::vec2 uv, bool stroke_start, bool stroke_end);
  // One history for the document's edits and the world's (world_edit): undo takes the newer top.
  bool undo();
  bool redo();
  // A change a panel made to the world (a component's value): undoable with the document's edits.
  void push_world_edit(std::string label, std::function<void(ecs::World&)> undo, std::function<void(ecs::World&)> redo);
  // A drag in progress on widget `id`: how to put back the value it started from (world_edit in panels.h).
  std::optional<std::pair<unsigned, std::function<void(ecs::World&)>>> world_drag;
  bool save();
  void message(EditorMessage::Level level, const std::string& text);
  const std::deque<EditorMessage>& messages() const { return messages_; }
  // The weather states the level names (scheduler, zones, triggers): not deleted or renamed under it.
  std::vector<std::string> states_in_use() const;
  void sync_live();  // the document's changed states -> the level's weather (library and preview) in the world

 private:
  void run_script_step();
  void execute(const ScriptAction& a);
  void hotkeys(const std::vector<std::pair<int, int>>& presses);
  void poll_disk();
  void draw_menu_bar();
  void draw_quit_prompt();
  void draw_conflicts();
  void draw_status();
  void draw_shader_errors();
  void update_preview();

  clouds::render::CloudFeature& clouds_;
  std::unique_ptr<WeatherDocument> doc_;
  std::unique_ptr<FolderWatch> watch_;  // the folder's files, stat-ed off the UI thread
  ecs::World* world_ = nullptr;
  app::WindowServices* window_ = nullptr;
  std::deque<EditorMessage> messages_;
  struct WorldEdit {
    std::string label;
    std::function<void(ecs::World&)> undo, redo;
    uint64_t serial = 0;
  };
  std::vector<WorldEdit> world_undo_, world_redo_;
  uint64_t newest_doc_serial_ = 0;  // a top step newer than this is a new document edit: the world's redo goes
  double time_s_ = 0.0;
  std::vector<std::string> conflicts_;  // changed on disk while edited here
  std::string last_shader_errors_;
  bool quit_prompt_ = false, quit_confirmed_ = false;
  bool show_messages_ = false;
  // The script.
  std::vector<ScriptAction> script_;
  std::filesystem::path script_file_;
  size_t script_pc_ = 0;
  uint32_t script_wait_ = 0;
  double script_resume_s_ = 0.0;  // a `wait` in seconds: run on from this time (a file's: give up then)
  double script_wait_limit_s_ = 0.0;
  std::optional<std::filesystem::path> script_wait_file_;
  bool script_waiting_screenshot_ = false;
  std::string script_error_;
  std::optional<std::filesystem::path> screenshot_request_;
};

}  // namespace cumulo::editor
