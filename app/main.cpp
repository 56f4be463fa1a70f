// cumulo: one executable, many subcommands. Errors at load boundaries arrive here as cumulo::Error
// and become a one-line message and exit code 1; nothing crashes on bad input.
#include <cstdio>
#include <exception>

#include "app/commands.h"
#include "engine/core/command.h"
#include "engine/core/error.h"

int main(int argc, char** argv) {
  const cumulo::app::Modules modules = cumulo::make_modules();
  cumulo::CommandRegistry registry;
  cumulo::register_all_commands(registry, modules);

  auto usage = [&](FILE* out) {
    std::fprintf(out, "usage: cumulo <command> [args]  (cumulo <command> --help for details)\n\ncommands:\n");
    for (auto& c : registry.all()) std::fprintf(out, "  %-12s %s\n", c.name.c_str(), c.summary.c_str());
  };
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  std::string name = argv[1];
  if (name == "-h" || name == "--help" || name == "help") {
    usage(stdout);
    return 0;
  }
  const cumulo::Command* cmd = registry.find(name);
  if (!cmd) {
    std::fprintf(stderr, "cumulo: unknown command \"%s\"\n", name.c_str());
    usage(stderr);
    return 2;
  }
  try {
    return cmd->run(argc - 1, argv + 1);
  } catch (const cumulo::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
