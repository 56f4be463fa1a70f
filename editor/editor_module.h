#pragma once
// The editor module (DESIGN.md: "editor/ -- the editor module: Dear ImGui panels after tonemap"):
// registers `cumulo edit LEVEL [every cumulo run flag] [--script FILE]`, which runs the level in a window
// with the editor's panels over it. In `cumulo run` the module is dormant (no flag, no pass, no UI).
//
//   cumulo edit content/levels/sample/level.json                                  # a person edits
//   xvfb-run -a cumulo edit content/levels/sample/level.json --weather-dir /tmp/w (continued:)
//       --size 640x360 --script tests/editor/data/edit_paint_save.json             # CI drives it
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/model/editor_script.h"
#include "engine/app/module.h"
#include "engine/gpu/buffer.h"

namespace cumulo::clouds {
class CloudsModule;
}

namespace cumulo::editor {

class Editor;
class ImGuiLayer;

class EditorModule final : public app::Module {
 public:
  explicit EditorModule(std::shared_ptr<clouds::CloudsModule> clouds);
  ~EditorModule() override;
  const char* name() const override { return "editor"; }
  void register_run_commands(CommandRegistry& registry, const app::Modules& all) override;
  void add_run_options(ArgParser& p) override;
  void on_window_open(app::WindowServices& services) override;
  app::InputClaim on_frame_input(ecs::World& world, const platform::InputState& input, double dt_s) override;
  bool allow_close(ecs::World& world) override;
  void on_window_close() override;
  void extract(const ecs::World& world, render::FrameSnapshot& snapshot) override;
  void add_passes(render::Stage stage, render::StageContext& f) override;

 private:
  int run_edit(int argc, char** argv, const app::Modules& all);
  void finish_screenshot();

  std::shared_ptr<clouds::CloudsModule> clouds_;
  bool editing_ = false;  // `cumulo edit` is running (else every hook is a no-op)
  std::string script_file_;
  std::vector<ScriptAction> script_;
  std::string script_error_;  // kept past the window (the exit code)
  app::WindowServices* services_ = nullptr;
  std::unique_ptr<ImGuiLayer> ui_;
  std::unique_ptr<Editor> editor_;
  // A screenshot of the presented image (UI included): read back in the frame, written at the next one.
  std::optional<std::filesystem::path> shot_path_;
  gpu::Buffer shot_buffer_;
  uint32_t shot_width_ = 0, shot_height_ = 0;
  bool shot_bgra_ = false;
  // The editor's CPU per frame (ImGui's frame, the panels, the live sync): the 1 ms budget.
  std::vector<double> cpu_ms_;
  bool first_frame_done_ = false;
};

std::shared_ptr<app::Module> make_editor_module(std::shared_ptr<clouds::CloudsModule> clouds);

}  // namespace cumulo::editor
