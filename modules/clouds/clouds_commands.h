#pragma once
#include "engine/core/command.h"

namespace cumulo::clouds {
// Registers the cloud module's subcommands: noise, bake, import.
void register_cloud_commands(CommandRegistry& registry);
}  // namespace cumulo::clouds
