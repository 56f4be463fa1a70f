#pragma once
// Modules: how a feature enters the engine without the engine knowing it (DESIGN.md "Modules"; a
// flecs module's one registration point, Granite's render-pass creators). app/main.cpp owns the list
// (clouds today, the editor later) and hands it to the command table and to `cumulo run`, whose
// headless and windowed loops drive every hook below in this order:
//
//   register_commands       once, at start-up: `cumulo <name>` subcommands
//   add_run_options         `cumulo run` flags of the module (parsed with the engine's), then
//   check_run_options       validation (throw cumulo::Error naming the flag)
//   register_components     before the level loads: component types with JSON (the level names them)
//   register_systems        systems in phases (ecs/scheduler.h)
//   on_level_loaded         the level's entities exist; resolve asset paths against level.directory
//   create_gpu              (render::RenderFeature) pipelines from the shared library, persistent images
//   extract                 every rendered frame: typed per-frame data into snapshot.extensions (and,
//                           for an atmosphere, snapshot.lighting)
//   add_passes              (render::RenderFeature) every frame, at each render::Stage
//   destroy_gpu             before the context goes, device idle
//
// Windowed runs only (an editor, a debug UI):
//   on_window_open          the window, context and renderer exist (create a UI's device objects)
//   on_frame_input          every frame after the window's events, before the fly camera and the
//                           simulation steps: build the UI, edit the world; returns the input it took
//   allow_close             the window was asked to close (its button, Esc): false keeps it open
//   on_window_close         before the renderer and the context go, device idle
//
// register_run_commands gets every module: a command that runs a level with all of them (`cumulo edit`).
//
// A short module with one component, one system and one compute pass:
//
//   struct Spin { float speed = 1.0f; };
//   class SpinModule : public app::Module {
//    public:
//     const char* name() const override { return "spin"; }
//     void register_components(ecs::ComponentRegistry& r) override {
//       r.register_component<Spin>("Spin", [](const Spin& s) { return Json{{"speed", s.speed}}; },
//                                  [](const JsonView& v) { return Spin{v.get<float>("speed", 1.0f)}; });
//     }
//     void register_systems(ecs::Scheduler& s) override {
//       s.add_system(ecs::Phase::Update, "spin", [](ecs::World& w, const ecs::FrameContext& f) {
//         w.view<const Spin, scene::Transform>().each([&](const Spin& s, scene::Transform& t) { ... });
//       });
//     }
//     void create_gpu(render::GpuServices& g) override { pipe_ = &g.library.compute({"spin/spin_tint.comp"}); }
//     void add_passes(render::Stage stage, render::StageContext& f) override {
//       if (stage != render::Stage::AfterOpaque) return;
//       f.graph.add_pass("spin tint", render::Queue::Compute,
//           [&](render::PassBuilder& b) { f.hdr = b.read_write(f.hdr, render::Usage::StorageWrite); },
//           [this, hdr = f.hdr](render::PassContext& c) { ... bind pipe_, push c.view(hdr), dispatch ... });
//     }
//    private:
//     gpu::Pipeline* pipe_ = nullptr;
//   };
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/app/module_hooks.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/render_feature.h"

namespace cumulo {
class ArgParser;
class CommandRegistry;
}  // namespace cumulo

namespace cumulo::app {

// The three concerns (module_hooks.h: SimulationHooks, WindowHooks; render::RenderFeature: create_gpu,
// add_passes, destroy_gpu) and what belongs to the whole module: its name, commands, flags and extraction.
class Module : public SimulationHooks, public render::RenderFeature, public WindowHooks {
 public:
  virtual const char* name() const = 0;
  virtual void register_commands(CommandRegistry&) {}
  virtual void add_run_options(ArgParser&) {}
  virtual void check_run_options() {}
  virtual void extract(const ecs::World&, render::FrameSnapshot&) {}
  // Commands that run a level with every module (their hooks, flags and passes).
  virtual void register_run_commands(CommandRegistry&, const Modules& /*all*/) {}
};

}  // namespace cumulo::app
