#pragma once
// Logging to stderr with a level prefix. Thread-safe. The level threshold comes from
// CUMULO_LOG=debug|info|warn|error (default info).
#include <string>

#include "engine/core/error.h"

namespace cumulo::log {

enum class Level { Debug, Info, Warn, Error };

void set_level(Level level);
Level level();
void write(Level level, const std::string& message);

#define CUMULO_LOG_IMPL(lvl, ...)                                                      \
  do {                                                                                 \
    if (::cumulo::log::level() <= (lvl)) ::cumulo::log::write((lvl), ::cumulo::strf(__VA_ARGS__)); \
  } while (0)
#define LOG_DEBUG(...) CUMULO_LOG_IMPL(::cumulo::log::Level::Debug, __VA_ARGS__)
#define LOG_INFO(...) CUMULO_LOG_IMPL(::cumulo::log::Level::Info, __VA_ARGS__)
#define LOG_WARN(...) CUMULO_LOG_IMPL(::cumulo::log::Level::Warn, __VA_ARGS__)
#define LOG_ERROR(...) CUMULO_LOG_IMPL(::cumulo::log::Level::Error, __VA_ARGS__)

}  // namespace cumulo::log
