#include "modules/clouds/clouds_module.h"

#include "modules/clouds/bake/bake_command.h"
#include "modules/clouds/bench_command.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/volume/import_command.h"

namespace cumulo::clouds {

void CloudsModule::register_commands(CommandRegistry& registry) {
  register_noise_command(registry);
  register_import_command(registry);
  register_bake_command(registry);
  register_bench_command(registry);
}

void CloudsModule::register_components(ecs::ComponentRegistry& registry) { register_cloudscape_component(registry); }

std::shared_ptr<app::Module> make_clouds_module() { return std::make_shared<CloudsModule>(); }

}  // namespace cumulo::clouds
