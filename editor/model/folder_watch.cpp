#include "editor/model/folder_watch.h"

#include <string>
#include <system_error>

namespace cumulo::editor {
namespace fs = std::filesystem;

FolderWatch::FolderWatch(fs::path folder, std::chrono::milliseconds period)
    : folder_(std::move(folder)), period_(period) {
  current_ = fingerprint(folder_);
  thread_ = std::thread([this] { run(); });
}

FolderWatch::~FolderWatch() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

uint64_t FolderWatch::fingerprint(const fs::path& folder) {
  // FNV-1a over each entry's name, size and mtime; directory order does not matter (entries are summed).
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec) return 0;
  uint64_t sum = 0x9e3779b97f4a7c15ull;
  for (const fs::directory_entry& e : it) {
    if (!e.is_regular_file(ec)) continue;
    uint64_t h = 1469598103934665603ull;
    auto mix = [&h](const void* data, size_t n) {
      for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(data)[i]) * 1099511628211ull;
    };
    const std::string name = e.path().filename().string();
    mix(name.data(), name.size());
    const uintmax_t size = e.file_size(ec);
    mix(&size, sizeof size);
    const auto mtime = e.last_write_time(ec).time_since_epoch().count();
    mix(&mtime, sizeof mtime);
    sum += h;
  }
  return sum;
}

bool FolderWatch::changed() {
  const uint64_t now = current_.load();
  const bool moved = first_ || now != seen_;
  seen_ = now;
  first_ = false;
  return moved;
}

void FolderWatch::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    if (wake_.wait_for(lock, period_, [this] { return stop_; })) break;
    lock.unlock();
    current_ = fingerprint(folder_);
    lock.lock();
  }
}

}  // namespace cumulo::editor
