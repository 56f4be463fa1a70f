#pragma once
// `cumulo bake RECIPE.json -o DIR [--slices DIR] [--seed N] [--voxel-size M] [--dims X,Y,Z]`
#include "engine/core/command.h"

namespace cumulo::clouds {

void register_bake_command(CommandRegistry& registry);
int run_bake_command(int argc, char** argv);

}  // namespace cumulo::clouds
