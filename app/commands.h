#pragma once
#include "engine/core/command.h"

namespace cumulo {
// Registers every subcommand of every layer (app/commands.cpp).
void register_all_commands(CommandRegistry& registry);
}  // namespace cumulo
