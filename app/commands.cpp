#include "app/commands.h"

#include "engine/app/application.h"
#include "engine/scene/tools/terrain_gen.h"
#include "editor/editor_module.h"
#include "modules/clouds/clouds_module.h"

// The one list of modules: add a line here when a module lands.

namespace cumulo {

app::Modules make_modules() {
  std::shared_ptr<clouds::CloudsModule> clouds = clouds::make_clouds_module();
  return {clouds, editor::make_editor_module(clouds)};  // the editor edits the clouds module's weather
}

void register_all_commands(CommandRegistry& registry, const app::Modules& modules) {
  for (const auto& m : modules) m->register_commands(registry);
  for (const auto& m : modules) m->register_run_commands(registry, modules);
  scene::register_scene_commands(registry);
  app::register_app_commands(registry, modules);
}

}  // namespace cumulo
