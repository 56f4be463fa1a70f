#include "engine/core/error.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace cumulo {

std::string vstrf(const char* fmt, va_list args) {
  va_list copy;
  va_copy(copy, args);
  int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  if (n <= 0) return {};
  std::string out(static_cast<size_t>(n), '\0');
  std::vsnprintf(out.data(), out.size() + 1, fmt, args);
  return out;
}

std::string strf(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  std::string s = vstrf(fmt, args);
  va_end(args);
  return s;
}

std::string bound_message(const std::string& m) {
  if (m.size() <= kMaxMessageToken) return m;
  std::string out;
  out.reserve(std::min(m.size(), kMaxMessageBytes + 64));
  size_t i = 0;
  while (i < m.size() && out.size() < kMaxMessageBytes) {
    if (m[i] == ' ' || m[i] == '\n') {
      out += m[i++];
      continue;
    }
    size_t end = i;
    while (end < m.size() && m[end] != ' ' && m[end] != '\n') ++end;
    const size_t n = end - i;
    if (n <= kMaxMessageToken) {
      out.append(m, i, n);
    } else {
      constexpr size_t kHead = 200, kTail = 60;
      out.append(m, i, kHead);
      out += "...";
      out.append(m, end - kTail, kTail);
      out += strf(" (%zu bytes)", n);
    }
    i = end;
  }
  if (i < m.size()) out += strf("... (message cut: %zu bytes)", m.size());
  return out;
}

Error::Error(const std::string& what) : std::runtime_error(bound_message(what)) {}

void fail(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  std::string s = vstrf(fmt, args);
  va_end(args);
  throw Error(s);
}

}  // namespace cumulo
