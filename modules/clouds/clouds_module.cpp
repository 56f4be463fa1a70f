#include "modules/clouds/clouds_module.h"

#include "modules/clouds/bake/bake_command.h"
#include "modules/clouds/noise/noise_command.h"
#include "modules/clouds/volume/import_command.h"

namespace cumulo::clouds {
namespace {

class CloudsModule final : public app::Module {
 public:
  const char* name() const override { return "clouds"; }
  void register_commands(CommandRegistry& registry) override {
    register_noise_command(registry);
    register_import_command(registry);
    register_bake_command(registry);
  }
};

}  // namespace

std::shared_ptr<app::Module> make_clouds_module() { return std::make_shared<CloudsModule>(); }

}  // namespace cumulo::clouds
