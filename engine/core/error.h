#pragma once
// Error handling policy: load boundaries (files, JSON, shaders, volumes, command lines) throw
// cumulo::Error with a message that names the file and the place; everything above catches it,
// reports it and keeps its last good state. Per-frame code does not throw.
#include <cstdarg>
#include <stdexcept>
#include <string>

namespace cumulo {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// printf-style formatting into a std::string (GCC 12 has no std::format).
std::string strf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string vstrf(const char* fmt, va_list args);

[[noreturn]] void fail(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace cumulo
