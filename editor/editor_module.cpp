#include "editor/editor_module.h"

#include <time.h>

#include <algorithm>
#include <cstdio>

#include "editor/editor.h"
#include "editor/ui/imgui_layer.h"
#include "engine/app/application.h"
#include "engine/app/run_options.h"
#include "engine/core/args.h"
#include "engine/core/command.h"
#include "engine/core/error.h"
#include "engine/core/png.h"
#include "engine/core/time.h"
#include "engine/gpu/context.h"
#include "engine/platform/window.h"
#include "engine/render/pass_helpers.h"
#include "modules/clouds/clouds_module.h"

namespace cumulo::editor {
namespace {

// This thread's CPU time: on a CPU Vulkan device the driver's threads render the previous frame on the
// same cores meanwhile, so wall-clock time would count their work as the editor's.
double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

}  // namespace

EditorModule::EditorModule(std::shared_ptr<clouds::CloudsModule> clouds) : clouds_(std::move(clouds)) {}
EditorModule::~EditorModule() = default;

void EditorModule::register_run_commands(CommandRegistry& registry, const app::Modules& all) {
  // The registry keeps the command (and so the module list) for the process's life.
  registry.add({"edit", "edit a level's weather live: Dear ImGui panels over the running level (needs a display)",
                [this, all](int argc, char** argv) { return run_edit(argc, argv, all); }});
}

void EditorModule::add_run_options(ArgParser& p) {
  if (!editing_) return;
  p.option("--script", "FILE",
           "run a JSON array of editor actions with no person (select_state, set, paint, undo, redo, save, event, wait, "
           "screenshot, quit, ...; README 'The weather editor')",
           &script_file_);
}

int EditorModule::run_edit(int argc, char** argv, const app::Modules& all) {
  editing_ = true;
  std::optional<app::RunOptions> o = app::parse_run_options(argc, argv, all, "cumulo edit");
  if (!o) return 0;
  // The whole script is checked before the window opens: a bad one changes nothing.
  if (!script_file_.empty()) script_ = load_editor_script(script_file_);
  o->require_window = true;
  if (o->frames_set) std::printf("cumulo: edit: --frames %u ends the session after that many frames\n", o->frames);
  const int code = app::run_level(*o, all);
  if (!cpu_ms_.empty()) {
    std::vector<double> v = cpu_ms_;
    std::sort(v.begin(), v.end());
    double sum = 0.0;
    for (double x : v) sum += x;
    std::printf("cumulo: editor CPU time per frame (its thread: ImGui frame, panels, live sync), %zu frames after the "
                "first: median %.3f ms, mean %.3f, p95 %.3f, max %.3f\n",
                v.size(), v[v.size() / 2], sum / double(v.size()), v[std::min(v.size() - 1, v.size() * 95 / 100)], v.back());
  }
  if (!script_error_.empty()) {
    std::fprintf(stderr, "error: %s\n", script_error_.c_str());
    return 1;
  }
  return code;
}

void EditorModule::on_window_open(app::WindowServices& services) {
  if (!editing_) return;
  services_ = &services;
  // The document first: a folder that cannot be opened stops the run before any UI exists.
  editor_ = std::make_unique<Editor>(clouds_->feature(), clouds_->weather_folder());
  ui_ = std::make_unique<ImGuiLayer>(services.window, services.ctx);
  if (!script_.empty()) editor_->set_script(std::move(script_), script_file_);
  std::printf("cumulo: editor open (Ctrl+Z undo, Ctrl+Shift+Z redo, Ctrl+S save; right mouse or Tab flies)\n");
}

app::InputClaim EditorModule::on_frame_input(ecs::World& world, const platform::InputState&, double dt_s) {
  if (!ui_) return {};
  if (shot_path_) finish_screenshot();
  const double start = thread_cpu_ms();
  ui_->begin_frame();
  std::vector<std::pair<int, int>> presses;
  for (const KeyPress& k : ui_->take_key_presses()) presses.emplace_back(k.key, k.mods);
  editor_->frame(world, *services_, dt_s, presses);
  ui_->end_frame();
  const double ms = thread_cpu_ms() - start;
  editor_->ui_cpu_ms = ms;
  editor_->ui_cpu_ms_max = std::max(editor_->ui_cpu_ms_max, ms);
  if (first_frame_done_) cpu_ms_.push_back(ms);  // the first frame lays the windows out
  first_frame_done_ = true;
  if (!editor_->script_error().empty()) script_error_ = editor_->script_error();
  return {ui_->wants_keyboard(), ui_->wants_mouse()};
}

bool EditorModule::allow_close(ecs::World&) { return !editor_ || editor_->allow_close(); }

void EditorModule::on_window_close() {
  if (!ui_ && !editor_) return;
  if (shot_path_) finish_screenshot();
  if (editor_ && !editor_->script_error().empty()) script_error_ = editor_->script_error();
  editor_.reset();
  shot_buffer_.reset();
  ui_.reset();
  services_ = nullptr;
}

void EditorModule::extract(const ecs::World&, render::FrameSnapshot& s) {
  if (editor_) editor_->set_camera(s.camera, s.width, s.height, s.sim_time);
}

void EditorModule::add_passes(render::Stage stage, render::StageContext& f) {
  if (stage != render::Stage::AfterTonemap || !ui_) return;
  ui_->add_pass(f);
  std::optional<std::filesystem::path> shot = editor_->take_screenshot_request();
  if (!shot) return;
  const VkFormat fmt = f.output_format;
  const bool bgra = fmt == VK_FORMAT_B8G8R8A8_UNORM || fmt == VK_FORMAT_B8G8R8A8_SRGB;
  if (!bgra && fmt != VK_FORMAT_R8G8B8A8_UNORM && fmt != VK_FORMAT_R8G8B8A8_SRGB) {
    editor_->screenshot_written(*shot, strf("screenshot %s: the window's format (%d) is not 8-bit RGBA", shot->string().c_str(), int(fmt)));
    return;
  }
  const VkExtent2D size = f.graph.output_size();
  shot_buffer_ = gpu::Buffer(f.ctx, {VkDeviceSize(size.width) * size.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     gpu::MemoryUsage::Readback, "editor.screenshot"});
  shot_width_ = size.width, shot_height_ = size.height, shot_bgra_ = bgra;
  render::add_readback_pass(f.graph, "editor.screenshot", {{f.output, shot_buffer_.handle()}}, shot_buffer_.size());
  shot_path_ = std::move(shot);
}

void EditorModule::finish_screenshot() {
  // The frame that read the image back was submitted since: wait for it (a screenshot is rare).
  services_->ctx.wait_idle();
  const std::filesystem::path path = *shot_path_;
  shot_path_.reset();
  std::string error;
  try {
    std::vector<uint8_t> rgba(size_t(shot_width_) * shot_height_ * 4);
    shot_buffer_.download(rgba.data(), rgba.size());
    for (size_t i = 0; i < rgba.size(); i += 4) {
      if (shot_bgra_) std::swap(rgba[i], rgba[i + 2]);
      rgba[i + 3] = 255;
    }
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    write_png(path, rgba.data(), shot_width_, shot_height_, 4);
  } catch (const std::exception& e) {
    error = e.what();
  }
  shot_buffer_.reset();
  if (editor_) editor_->screenshot_written(path, error);
}

std::shared_ptr<app::Module> make_editor_module(std::shared_ptr<clouds::CloudsModule> clouds) {
  if (!clouds) fail("editor: needs the clouds module");
  return std::make_shared<EditorModule>(std::move(clouds));
}

}  // namespace cumulo::editor
