#pragma once
// `cumulo run`: the application loop (DESIGN.md "The frame").
//
//   input -> fixed-step simulation (ECS systems in phases, deterministic given the seed)
//         -> extract a read-only FrameSnapshot -> FrameRenderer builds + executes the render graph
//         -> present (windowed) or read back (headless screenshot)
//
// Headless runs open no window (GLFW is never initialized) and advance the simulation by exactly
// 1/mode seconds per frame, so a run is reproducible. Windowed runs pace frames to the budget mode,
// fly the camera with WASD + mouse and hot-reload shaders.
#include "engine/app/run_options.h"

namespace cumulo {
class CommandRegistry;
}

namespace cumulo::app {

// Runs a level; returns the process exit code. Throws cumulo::Error for bad inputs (level, glTF,
// shaders, flags) so main() prints one clear line.
int run_level(const RunOptions& options, const Modules& modules = {});

// Registers `cumulo run` with the given modules (their flags, components, systems and passes).
void register_app_commands(CommandRegistry& registry, const Modules& modules);

}  // namespace cumulo::app
