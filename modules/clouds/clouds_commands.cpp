#include "modules/clouds/clouds_commands.h"

#include "modules/clouds/bake/bake_command.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/volume/import_command.h"

// One line per tool as it lands: each tool's header declares its register_*_command().

namespace cumulo::clouds {

void register_cloud_commands(CommandRegistry& registry) {
  register_noise_command(registry);
  register_import_command(registry);
  register_bake_command(registry);
  (void)registry;
}

}  // namespace cumulo::clouds
