#pragma once
// `cumulo import`: OpenVDB files or TGA-slice NVDFs -> modeling.nvdf + field.nvdf (see import.h).
#include "engine/core/command.h"

namespace cumulo::clouds {

void register_import_command(CommandRegistry& registry);

}  // namespace cumulo::clouds
