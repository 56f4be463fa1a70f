#include "engine/core/log.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace cumulo::log {
namespace {

Level initial_level() {
  const char* env = std::getenv("CUMULO_LOG");
  if (!env) return Level::Info;
  if (!std::strcmp(env, "debug")) return Level::Debug;
  if (!std::strcmp(env, "warn")) return Level::Warn;
  if (!std::strcmp(env, "error")) return Level::Error;
  return Level::Info;
}

std::atomic<Level> g_level{initial_level()};
std::mutex g_mutex;

}  // namespace

void set_level(Level l) { g_level = l; }
Level level() { return g_level; }

void write(Level l, const std::string& message) {
  static const char* names[] = {"debug", "info", "warn", "error"};
  std::lock_guard lock(g_mutex);
  std::fprintf(stderr, "[%s] %s\n", names[static_cast<int>(l)], message.c_str());
}

}  // namespace cumulo::log
