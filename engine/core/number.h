#pragma once
// The one rule for every number that comes from outside (JSON, command lines, binary headers):
// it must be finite and still in range once narrowed to the type it is stored in. A double that
// only overflows a float (1e39) would otherwise become +inf; an integer past 32 bits would wrap.
//
//   if (auto why = number_problem<float>(v)) fail("%s: %s", where, why->c_str());
//   float f = narrow_number<float>(v, [&](const std::string& why) { view.fail(why); });
//
// Callers add their own semantic range (0 < radius <= 1e6) after this check; this one only says
// whether the value can be stored at all.
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "engine/core/error.h"

namespace cumulo {

// T for messages, with its article ("a 32-bit float", "an unsigned 32-bit integer").
template <typename T>
constexpr const char* number_type_name() {
  if constexpr (std::is_same_v<T, float>) return "a 32-bit float";
  else if constexpr (std::is_same_v<T, double>) return "a 64-bit float";
  else if constexpr (std::is_signed_v<T>)
    return sizeof(T) == 8 ? "a 64-bit integer" : sizeof(T) == 4 ? "a 32-bit integer" : sizeof(T) == 2 ? "a 16-bit integer" : "an 8-bit integer";
  else
    return sizeof(T) == 8 ? "an unsigned 64-bit integer" : sizeof(T) == 4 ? "an unsigned 32-bit integer" : sizeof(T) == 2 ? "an unsigned 16-bit integer" : "an unsigned 8-bit integer";
}

// Why `v` cannot be stored as a T, or nothing when it can (integers must also be whole).
template <typename T>
std::optional<std::string> number_problem(double v) {
  if (!std::isfinite(v)) return strf("expected a finite number, got %g", v);
  if constexpr (std::is_floating_point_v<T>) {
    if (std::abs(v) > double(std::numeric_limits<T>::max()))
      return strf("%g does not fit %s (|x| <= %g)", v, number_type_name<T>(), double(std::numeric_limits<T>::max()));
  } else {
    static_assert(std::is_integral_v<T>);
    if (v != std::floor(v)) return strf("expected an integer, got %g", v);
    // The upper bound is compared as "v < max + 1" because max itself may not be a double (2^63 - 1).
    const double lo = double(std::numeric_limits<T>::min()), hi_excl = double(std::numeric_limits<T>::max()) + 1.0;
    if (v < lo || v >= hi_excl)
      return strf("%.17g does not fit %s (%s..%s)", v, number_type_name<T>(),
                  std::to_string(std::numeric_limits<T>::min()).c_str(), std::to_string(std::numeric_limits<T>::max()).c_str());
  }
  return std::nullopt;
}

// The same rule for integers read exactly (64-bit JSON integers, command-line text), so values past
// 2^53 are not rounded through a double first.
template <typename T, typename I>
std::optional<std::string> integer_problem(I v) {
  static_assert(std::is_integral_v<T> && std::is_integral_v<I>);
  if (!std::in_range<T>(v))
    return strf("%s does not fit %s (%s..%s)", std::to_string(v).c_str(), number_type_name<T>(),
                std::to_string(std::numeric_limits<T>::min()).c_str(), std::to_string(std::numeric_limits<T>::max()).c_str());
  return std::nullopt;
}

// Checks and narrows; `on_error(message)` must throw (it is given the reason, the caller adds the place).
template <typename T, typename OnError>
T narrow_number(double v, OnError&& on_error) {
  if (auto why = number_problem<T>(v)) on_error(*why);
  return static_cast<T>(v);
}

}  // namespace cumulo
