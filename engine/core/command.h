#pragma once
// The `cumulo` executable's subcommands. Each layer registers its own (engine: run, bench;
// modules/clouds: noise, bake, import; editor: edit) so app/main.cpp only wires them together.
#include <functional>
#include <string>
#include <vector>

namespace cumulo {

struct Command {
  std::string name;
  std::string summary;                         // one line for `cumulo --help`
  std::function<int(int argc, char** argv)> run;  // argv[0] is the subcommand name
};

class CommandRegistry {
 public:
  void add(Command c) { commands_.push_back(std::move(c)); }
  const std::vector<Command>& all() const { return commands_; }
  const Command* find(const std::string& name) const {
    for (auto& c : commands_)
      if (c.name == name) return &c;
    return nullptr;
  }

 private:
  std::vector<Command> commands_;
};

}  // namespace cumulo
