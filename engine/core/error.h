#pragma once
// Error handling policy: load boundaries (files, JSON, shaders, volumes, command lines) throw
// cumulo::Error with a message that names the file and the place; everything above catches it,
// reports it and keeps its last good state. Per-frame code does not throw.
#include <cstdarg>
#include <stdexcept>
#include <string>

namespace cumulo {

// Every message is bounded where it is made (bound_message): no site can echo an unbounded input whole (a 2 MB string
// used as a model path came back as a 2 MB message).
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what);
  explicit Error(const char* what) : Error(std::string(what ? what : "")) {}
};

// `message` with every run of more than kMaxMessageToken bytes without a space cut in its middle ("head...tail (N
// bytes)"), and the whole cut after kMaxMessageBytes: an outside value quoted or clipped at its site (message.h) is
// left as it is; one that was not is still bounded.
inline constexpr size_t kMaxMessageToken = 512;
inline constexpr size_t kMaxMessageBytes = 8192;
std::string bound_message(const std::string& message);

// printf-style formatting into a std::string (GCC 12 has no std::format).
std::string strf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string vstrf(const char* fmt, va_list args);

[[noreturn]] void fail(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace cumulo
