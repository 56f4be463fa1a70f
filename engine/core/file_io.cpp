#include "engine/core/file_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "engine/core/error.h"

namespace cumulo {
namespace fs = std::filesystem;

std::vector<uint8_t> read_file_bytes(const fs::path& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) fail("%s: cannot open: %s", path.c_str(), std::strerror(errno));
  // Only regular files, read to the size they have when opened: a device (/dev/zero) or a pipe has
  // no end, and reading one grew memory until std::bad_alloc, which named nothing.
  struct stat st;
  if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::fclose(f);
    fail("%s: not a regular file", path.c_str());
  }
  if (uint64_t(st.st_size) > kMaxReadBytes) {
    std::fclose(f);
    fail("%s: %llu bytes is over the %llu-byte limit for one input file", path.c_str(),
         static_cast<unsigned long long>(st.st_size), static_cast<unsigned long long>(kMaxReadBytes));
  }
  std::vector<uint8_t> data(static_cast<size_t>(st.st_size));
  const size_t n = std::fread(data.data(), 1, data.size(), f);
  const bool err = std::ferror(f);
  std::fclose(f);
  if (err) fail("%s: read error", path.c_str());
  data.resize(n);  // the file shrank while it was read: what was there
  return data;
}

std::string read_file_text(const fs::path& path) {
  auto bytes = read_file_bytes(path);
  return std::string(bytes.begin(), bytes.end());
}

namespace {

// Writes PATH.tmp (creating the folder) and flushes it to disk; returns the temporary's path. The
// temporary is removed when anything fails. A target that is an existing folder is refused here,
// so no rename can fail on it later.
fs::path write_temporary(const fs::path& path, std::span<const uint8_t> bytes) {
  if (path.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) fail("%s: cannot create folder %s: %s", path.c_str(), path.parent_path().c_str(), ec.message().c_str());
  }
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail("%s: cannot replace: it is a folder", path.c_str());
  fs::path tmp = path;
  tmp += ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail("%s: cannot write: %s", tmp.c_str(), std::strerror(errno));
  bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  ok = std::fflush(f) == 0 && ok;
  ok = fsync(fileno(f)) == 0 && ok;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) {
    const int err = errno;
    std::remove(tmp.c_str());
    fail("%s: write failed: %s", path.c_str(), std::strerror(err));
  }
  return tmp;
}

void rename_into_place(const fs::path& tmp, const fs::path& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);  // a failed save leaves nothing behind
    fail("%s: cannot replace: %s", path.c_str(), why.c_str());
  }
}

std::span<const uint8_t> text_bytes(const std::string& text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

}  // namespace

void write_file_atomic(const fs::path& path, std::span<const uint8_t> bytes) {
  rename_into_place(write_temporary(path, bytes), path);
}

void write_file_atomic(const fs::path& path, const std::string& text) { write_file_atomic(path, text_bytes(text)); }

FileSet::~FileSet() {
  std::error_code ec;
  for (const Entry& e : entries_) fs::remove(e.temp, ec);
}

void FileSet::add(const fs::path& path, std::span<const uint8_t> bytes) {
  for (const Entry& e : entries_)
    if (e.target == path) fail("%s: written twice in one set", path.c_str());
  fs::path tmp = write_temporary(path, bytes);  // on failure the destructor removes the earlier ones
  entries_.push_back({path, std::move(tmp)});
}

void FileSet::add(const fs::path& path, const std::string& text) { add(path, text_bytes(text)); }

void FileSet::commit() {
  // Every file is on disk under its temporary name and no target is a folder: the renames (same
  // folder, same file system) are what remains.
  std::vector<Entry> pending = std::move(entries_);
  entries_.clear();
  for (size_t i = 0; i < pending.size(); ++i) {
    std::error_code ec;
    fs::rename(pending[i].temp, pending[i].target, ec);
    if (ec) {
      const std::string why = ec.message();
      for (size_t j = i; j < pending.size(); ++j) fs::remove(pending[j].temp, ec);
      fail("%s: cannot replace: %s", pending[i].target.c_str(), why.c_str());
    }
  }
}

fs::path repo_root() {
  if (const char* env = std::getenv("CUMULO_ROOT")) return fs::path(env);
  // Markers only the source tree has: the build folder also holds shaders/ (SPIR-V) and content/ (bakes).
  auto is_root = [](const fs::path& p) {
    return fs::exists(p / "shaders" / "CMakeLists.txt") && fs::exists(p / "content" / "levels");
  };
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (fs::path start : {exe.parent_path(), fs::current_path()}) {
    for (fs::path p = start; !p.empty(); p = p.parent_path()) {
      if (is_root(p)) return p;
      if (p == p.parent_path()) break;
    }
  }
  return fs::current_path();
}

}  // namespace cumulo
