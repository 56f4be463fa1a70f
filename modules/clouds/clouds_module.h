#pragma once
// The cloud module's one registration point (DESIGN.md "Modules"): its subcommands (noise, bake,
// import) today; its components, systems and render passes as they land (clouds_module.cpp).
#include <memory>

#include "engine/app/module.h"

namespace cumulo::clouds {

std::shared_ptr<app::Module> make_clouds_module();

}  // namespace cumulo::clouds
