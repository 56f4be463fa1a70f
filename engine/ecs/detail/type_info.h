#pragma once
// Dense per-process ids and readable names for component, event and resource types.
#include <cstdint>
#include <string_view>

namespace cumulo::ecs::detail {

uint32_t next_type_id();  // thread-safe counter, world.cpp

// One id per type for the whole program (an inline function's static is merged across libraries).
template <typename T>
uint32_t type_id() {
  static const uint32_t id = next_type_id();
  return id;
}

// "cumulo::scene::Transform" from GCC/Clang's __PRETTY_FUNCTION__; used only in error messages.
template <typename T>
constexpr std::string_view type_name() {
  std::string_view f = __PRETTY_FUNCTION__;
  const std::string_view key = "T = ";
  size_t b = f.find(key);
  if (b == std::string_view::npos) return "?";
  b += key.size();
  size_t e = f.find_first_of(";]", b);
  return f.substr(b, e - b);
}
// Forces compile-time evaluation, so hot paths that pass the name along for errors pay nothing.
template <typename T>
inline constexpr std::string_view type_name_v = type_name<T>();

}  // namespace cumulo::ecs::detail
