#include "app/commands.h"

#include "engine/app/application.h"
#include "engine/scene/tools/terrain_gen.h"
#include "modules/clouds/clouds_module.h"

// The one list of modules: add a line here when a module lands (the editor next).

namespace cumulo {

app::Modules make_modules() { return {clouds::make_clouds_module()}; }

void register_all_commands(CommandRegistry& registry, const app::Modules& modules) {
  for (const auto& m : modules) m->register_commands(registry);
  scene::register_scene_commands(registry);
  app::register_app_commands(registry, modules);
}

}  // namespace cumulo
