#pragma once
// A small command-line parser shared by every `cumulo` subcommand, so all of them take
// `--name VALUE` / `--name=VALUE`, print the same `--help`, and reject unknown flags clearly.
//
//   ArgParser p("cumulo noise", "Generate tileable cloud noises.");
//   p.option("-o", "DIR", "output folder", &out).option("--seed", "N", "random seed", &seed);
//   p.option("--voxel-size", "M", "voxel size", &voxel).range(0.0, 1024.0, Open::Low);   // 0 < M <= 1024
//   if (!p.parse(argc, argv)) return 0;   // --help was printed
//
// Numbers follow the one rule for outside numbers (core/number.h): finite, in range of the type they
// are stored in (4294967312 is not an int, nan and 1e39 are not floats), then in the option's range.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/enum_names.h"

namespace cumulo {

// `text` as a T for the flag `flag`, by the rule above; throws "FLAG: ..." naming the value.
template <typename T>
T parse_flag_number(const std::string& flag, const std::string& text);
// "a,b,c": exactly n comma-separated numbers, each by parse_flag_number.
template <typename T>
std::vector<T> parse_flag_list(const std::string& flag, const std::string& text, size_t n);

// Which ends of a range() are excluded.
enum class Open { None, Low, High, Both };

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
  // One of a table's names (engine/core/enum_names.h; the table must outlive the parser, as the
  // inline constexpr tables do); --help shows them as a|b|c, a bad one fails naming all of them.
  template <typename E, size_t N>
  ArgParser& choice(const std::string& name, const std::array<EnumName<E>, N>& table, const std::string& help, E* out) {
    return option(name, names_choice(table), help,
                  [name, t = &table, out](const std::string& s) { *out = parse_name_or_fail(*t, name, s); });
  }
  // The same into an optional, with one more name that leaves it empty (auto, preset: decided later).
  template <typename E, size_t N>
  ArgParser& choice(const std::string& name, const std::array<EnumName<E>, N>& table, const char* unset,
                    const std::string& help, std::optional<E>* out) {
    return option(name, names_choice(table) + "|" + unset, help, [name, t = &table, unset, out](const std::string& s) {
      if (s == unset) {
        out->reset();
        return;
      }
      if (const std::optional<E> v = parse_name(*t, s)) {
        *out = *v;
        return;
      }
      std::string names;
      for (const EnumName<E>& row : *t) names += std::string(row.name) + ", ";
      fail("%s: expected %s or %s, got %s", name.c_str(), names.substr(0, names.size() - 2).c_str(), unset, quote(s).c_str());
    });
  }
  ArgParser& on_off(const std::string& name, const std::string& help, bool* out) {
    return choice(name, kOnOffNames, help, out);
  }
  // The range of the numeric option added last ("--iso: -1 is outside 0..1"); also shown by --help.
  ArgParser& range(double lo, double hi, Open open = Open::None);

  // argv[0] is the subcommand name. Returns false after printing --help. Throws cumulo::Error on
  // unknown flags, missing values, bad numbers or missing positionals.
  bool parse(int argc, char** argv);
  bool was_set(const std::string& name) const;
  std::string help() const;

 private:
  struct Range {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    Open open = Open::None;
    bool set = false;
  };
  struct Opt {
    std::string name, value, help;
    std::function<void(const std::string&, const Opt&)> set;
    bool is_flag = false;
    Range range;
  };
  template <typename T>
  ArgParser& number_option(const std::string& name, const std::string& value, const std::string& help, T* out);
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
