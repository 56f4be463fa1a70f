#pragma once
// A module's hooks by concern (module.h puts them together in app::Module). The simulation's need only
// the ECS and the level, so a simulation-only component and its system compile without the render graph
// or Vulkan; the window's are called by windowed runs only.
#include <memory>
#include <vector>

#include "engine/app/input_claim.h"
#include "engine/ecs/scheduler.h"
#include "engine/ecs/serialize.h"
#include "engine/ecs/world.h"
#include "engine/scene/level.h"

namespace cumulo::gpu {
class Context;
}
namespace cumulo::platform {
class Window;
}
namespace cumulo::render {
class FrameRenderer;
class DynamicResolution;
enum class BudgetMode : uint8_t;
}  // namespace cumulo::render

namespace cumulo::app {

class Module;
using Modules = std::vector<std::shared_ptr<Module>>;

// Before the level loads: component types with JSON (the level names them) and systems in phases; then
// the level's entities exist.
class SimulationHooks {
 public:
  virtual ~SimulationHooks() = default;
  virtual void register_components(ecs::ComponentRegistry&) {}
  virtual void register_systems(ecs::Scheduler&) {}
  // Throws cumulo::Error naming the level file and the place on a bad asset; the run then stops.
  virtual void on_level_loaded(ecs::World&, const scene::LevelInfo&) {}
};

// What a windowed run lends a module's UI: valid from on_window_open to on_window_close.
struct WindowServices {
  platform::Window& window;
  gpu::Context& ctx;
  render::FrameRenderer& renderer;
  render::BudgetMode& mode;  // the run's budget mode: a UI may switch it between frames
  render::DynamicResolution& resolution;  // the run's dynamic resolution: a UI may switch it or its budget
};

// Windowed runs only (an editor, a debug UI).
class WindowHooks {
 public:
  virtual ~WindowHooks() = default;
  virtual void on_window_open(WindowServices&) {}
  // Every frame after the window's events, before the fly camera and the simulation steps: build the UI,
  // edit the world; returns the input it took.
  virtual InputClaim on_frame_input(ecs::World&, const platform::InputState&, double /*dt_s*/) { return {}; }
  // The window was asked to close (its button, Esc): false keeps it open.
  virtual bool allow_close(ecs::World&) { return true; }
  virtual void on_window_close() {}
};

}  // namespace cumulo::app
