#pragma once
// An exclusive advisory lock on a file for the lifetime of the object (flock: released if the process
// dies), so two processes that fill the same cache entry wait for each other instead of racing.
//
//   FileLock lock(dir.string() + ".lock");   // blocks until this process holds it
#include <filesystem>

namespace cumulo {

class FileLock {
 public:
  explicit FileLock(const std::filesystem::path& path);  // throws cumulo::Error naming the path
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

// The per-user cache folder: $CUMULO_CACHE_DIR, else $XDG_CACHE_HOME/cumulo, else ~/.cache/cumulo.
std::filesystem::path cache_dir();

}  // namespace cumulo
