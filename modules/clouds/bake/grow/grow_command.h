#pragma once
// `cumulo grow SPEC.json -o DIR [--steps N]`: the cloud-formation simulation (grow_spec.h, solver.h).
#include "engine/core/command.h"

namespace cumulo::clouds {

void register_grow_command(CommandRegistry& registry);
int run_grow_command(int argc, char** argv);

}  // namespace cumulo::clouds
