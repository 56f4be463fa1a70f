#pragma once
// One name table per enum: the spellings a flag, a JSON file or a report uses, printed and parsed from
// the same rows so the two cannot drift apart (before this, every enum had a switch for its name and a
// loop or an if-chain for its parse, and the error texts listed the values by hand).
//
//   inline constexpr std::array kAblationNames{EnumName<CloudAblation>{CloudAblation::Base, "base"}, ...};
//   name_of(kAblationNames, a)                          // "base" ("?" for a value not in the table)
//   parse_name(kAblationNames, "full")                  // std::optional<CloudAblation>
//   parse_name_or_fail(kAblationNames, "--x", text)     // throws "--x: expected base, voxel-lighting or full, got "y""
//   ArgParser::choice("--cloud-ablation", kAblationNames, help, &out)   // engine/core/args.h
//
// The value may be any copyable type with ==: an enum, bool (on|off), or numbers spelled differently
// from their value (--cloud-reprojection 16 is a block of 4).
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "engine/core/error.h"
#include "engine/core/message.h"

namespace cumulo {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

template <typename E, size_t N>
constexpr const char* name_of(const std::array<EnumName<E>, N>& table, E value) {
  for (const EnumName<E>& row : table)
    if (row.value == value) return row.name;
  return "?";
}

template <typename E, size_t N>
constexpr std::optional<E> parse_name(const std::array<EnumName<E>, N>& table, std::string_view text) {
  for (const EnumName<E>& row : table)
    if (text == row.name) return row.value;
  return std::nullopt;
}

// "a, b or c": the accepted names for an error text.
template <typename E, size_t N>
std::string names_list(const std::array<EnumName<E>, N>& table) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += std::string(i == 0 ? "" : i + 1 == N ? " or " : ", ") + table[i].name;
  return s;
}

// "a|b|c": the accepted names for a flag's --help.
template <typename E, size_t N>
std::string names_choice(const std::array<EnumName<E>, N>& table) {
  std::string s;
  for (size_t i = 0; i < N; ++i) s += std::string(i == 0 ? "" : "|") + table[i].name;
  return s;
}

// Throws "WHERE: expected a, b or c, got "text"".
template <typename E, size_t N>
E parse_name_or_fail(const std::array<EnumName<E>, N>& table, const std::string& where, std::string_view text) {
  if (const std::optional<E> v = parse_name(table, text)) return *v;
  fail("%s: expected %s, got %s", where.c_str(), names_list(table).c_str(), quote(text).c_str());
}

// on|off, the spelling of every boolean flag.
inline constexpr std::array kOnOffNames{EnumName<bool>{true, "on"}, EnumName<bool>{false, "off"}};

}  // namespace cumulo
