#include "app/commands.h"

#include "engine/app/application.h"
#include "engine/scene/tools/terrain_gen.h"
#include "modules/clouds/clouds_commands.h"

// Each layer adds its own register_*_commands(); add one line here when a layer gains commands.

namespace cumulo {

void register_all_commands(CommandRegistry& registry) {
  clouds::register_cloud_commands(registry);
  scene::register_scene_commands(registry);
  app::register_app_commands(registry);
}

}  // namespace cumulo
