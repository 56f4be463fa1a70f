#pragma once
// `cumulo soak LEVEL`: hours of play in minutes. A headless run flies a loop through the level (soak_path.h) with
// everything the game does switched on along it: the weather scheduler on short holds and every state forced in
// turn, the day cycling through the night, lightning every 1.5 s, the Stormbird killed and brought back, the growing
// clouds (CloudGrowth) reset and started again at each lap's start, the budget
// mode switching 30 / 40 / 60 Hz, the clouds' debug views toggled. Every lap (a window of frames) it records the
// process's resident memory, GPU memory per resource, the render graph's shapes, pipelines, descriptor sets,
// images and buffers, the frames' CPU, GPU and wall ms, validation messages and the frames holding a NaN or an
// infinity (counted on the GPU). It prints a table, writes JSON (--out) and checks that nothing grows.
#include "engine/core/command.h"
#include "modules/clouds/options/clouds_run.h"

namespace cumulo::clouds {

void register_soak_command(CommandRegistry& registry, const CloudsRun& clouds);

}  // namespace cumulo::clouds
