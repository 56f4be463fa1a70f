#pragma once
// A folder's files watched from a thread of their own: every `period` it lists the folder and folds each
// file's name, size and modification time into a fingerprint; changed() says (once) that it moved. The
// editor then asks its WeatherDocument to poll_disk() on the UI thread, so the UI thread does no file
// system calls while nothing changes.
//
//   FolderWatch watch("content/weather", std::chrono::milliseconds(500));
//   if (watch.changed()) events = doc.poll_disk();
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <thread>

namespace cumulo::editor {

class FolderWatch {
 public:
  FolderWatch(std::filesystem::path folder, std::chrono::milliseconds period);
  ~FolderWatch();  // stops the thread (within one period at most: it is woken)
  FolderWatch(const FolderWatch&) = delete;
  FolderWatch& operator=(const FolderWatch&) = delete;

  // True once after the fingerprint moved since the last call (and on the first call).
  bool changed();
  // The folder's fingerprint now (name, size and mtime of every regular file); 0 for a folder that
  // cannot be listed.
  static uint64_t fingerprint(const std::filesystem::path& folder);

 private:
  void run();
  std::filesystem::path folder_;
  std::chrono::milliseconds period_;
  std::atomic<uint64_t> current_{0};
  uint64_t seen_ = 0;
  bool first_ = true;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace cumulo::editor
