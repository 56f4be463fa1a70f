#pragma once
#include "engine/app/module.h"
#include "engine/core/command.h"

namespace cumulo {
// The modules of this executable, in registration order (app/commands.cpp).
app::Modules make_modules();
// Registers every subcommand: the engine's (run, gen-terrain) and every module's.
void register_all_commands(CommandRegistry& registry, const app::Modules& modules);
}  // namespace cumulo
