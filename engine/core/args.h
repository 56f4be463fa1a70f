#pragma once
// A small command-line parser shared by every `cumulo` subcommand, so all of them take
// `--name VALUE` / `--name=VALUE`, print the same `--help`, and reject unknown flags clearly.
//
//   ArgParser p("cumulo noise", "Generate tileable cloud noises.");
//   p.option("-o", "DIR", "output folder", &out).option("--seed", "N", "random seed", &seed);
//   if (!p.parse(argc, argv)) return 0;   // --help was printed
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cumulo {

class ArgParser {
 public:
  ArgParser(std::string command, std::string summary);

  ArgParser& positional(const std::string& name, const std::string& help, std::string* out, bool required = true);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, std::string* out);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, int* out);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, uint32_t* out);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, uint64_t* out);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, float* out);
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help, double* out);
  // Custom conversion: the setter throws cumulo::Error for a bad value.
  ArgParser& option(const std::string& name, const std::string& value, const std::string& help,
                    std::function<void(const std::string&)> set);
  ArgParser& flag(const std::string& name, const std::string& help, bool* out);

  // argv[0] is the subcommand name. Returns false after printing --help. Throws cumulo::Error on
  // unknown flags, missing values, bad numbers or missing positionals.
  bool parse(int argc, char** argv);
  bool was_set(const std::string& name) const;
  std::string help() const;

 private:
  struct Opt {
    std::string name, value, help;
    std::function<void(const std::string&)> set;
    bool is_flag = false;
  };
  struct Pos {
    std::string name, help;
    std::string* out;
    bool required;
  };
  const Opt* find(const std::string& name) const;
  std::string command_, summary_;
  std::vector<Opt> opts_;
  std::vector<Pos> pos_;
  std::vector<std::string> set_;
};

}  // namespace cumulo
