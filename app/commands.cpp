#include "app/commands.h"

// Each layer adds its own register_*_commands(); add one line here when a layer gains commands.

namespace cumulo {

void register_all_commands(CommandRegistry& registry) {
  (void)registry;
}

}  // namespace cumulo
