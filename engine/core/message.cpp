#include "engine/core/message.h"

#include <algorithm>

#include "engine/core/error.h"

namespace cumulo {

namespace {

// The first `max` bytes of `value` with control characters escaped (a message stays one line).
std::string escaped_prefix(std::string_view value, size_t max) {
  std::string out;
  for (size_t i = 0; i < std::min(value.size(), max); ++i) {
    const unsigned char c = static_cast<unsigned char>(value[i]);
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) out += strf("\\x%02x", c);
    else out += char(c);
  }
  return out;
}

std::string length_note(std::string_view value, size_t max) {
  return value.size() > max ? strf("... (%zu bytes)", value.size()) : std::string();
}

}  // namespace

std::string clip(std::string_view value, size_t max) {
  return escaped_prefix(value, max) + length_note(value, max);
}

// The length note goes after the closing quote: it is not part of the value.
std::string quote(std::string_view value, size_t max) {
  return "\"" + escaped_prefix(value, max) + "\"" + length_note(value, max);
}

std::string library_message(std::string_view what) {
  std::string s(what);
  // nlohmann: "[json.exception.<kind>.<id>] message"
  if (s.rfind("[json.exception.", 0) == 0) {
    const size_t close = s.find("] ");
    if (close != std::string::npos) s.erase(0, close + 2);
  }
  // OpenVDB: "<Kind>Error: message" (openvdb/Exceptions.h), possibly repeated when rethrown.
  for (bool again = true; again;) {
    again = false;
    for (const char* prefix : {"IoError: ", "RuntimeError: ", "ValueError: ", "TypeError: ", "KeyError: ",
                               "IndexError: ", "LookupError: ", "NotImplementedError: ", "ReferenceError: ",
                               "ArithmeticError: "}) {
      if (s.rfind(prefix, 0) == 0) {
        s.erase(0, std::string_view(prefix).size());
        again = true;
      }
    }
  }
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  std::string joined;
  for (char c : s) {
    if (c == '\n') joined += "; ";
    else if (c != '\r') joined += c;
  }
  return clip(joined, 300);
}

}  // namespace cumulo
