#include "engine/core/file_io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "engine/core/error.h"
#include "engine/core/file_lock.h"
#include "engine/core/hash.h"

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

// CUMULO_KILL_AT_SAVE_STEP=N: the N-th step of this process's file-set writes kills it (tests of a save killed
// midway; file_io.h).
void save_step() {
  static const long at = [] {
    const char* e = std::getenv("CUMULO_KILL_AT_SAVE_STEP");
    return e ? std::strtol(e, nullptr, 10) : 0L;
  }();
  static long step = 0;
  if (at > 0 && ++step == at) {
    std::fflush(stdout);
    std::fflush(stderr);
    ::kill(::getpid(), SIGKILL);
  }
}

// Flushes a folder's entries (the renames in it) to disk; best effort.
void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// The folder's file-set lock (flock: released by the kernel when the holder dies, so a killed save never blocks the
// next). Blocking: a second writer waits for the first; with `wait` false, -1 when another process holds it.
int lock_folder(const fs::path& folder, bool wait) {
  // In the user's cache folder, keyed by the folder's absolute path: no lock file is left in the folders written.
  std::error_code ec;
  const fs::path where = fs::weakly_canonical(fs::absolute(folder.empty() ? fs::path(".") : folder), ec);
  const fs::path dir = cache_dir() / "locks";
  fs::create_directories(dir, ec);
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.lock", static_cast<unsigned long long>(hash64(where.string())));
  const int fd = ::open((dir / name).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return -2;  // no cache folder: saves are not serialized, recovery goes ahead
  if (::flock(fd, LOCK_EX | (wait ? 0 : LOCK_NB)) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

void unlock_folder(int& fd) {
  if (fd >= 0) ::close(fd);  // closing releases the flock
  fd = -1;
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
  unlock_folder(lock_fd_);
}

void FileSet::add(const fs::path& path, std::span<const uint8_t> bytes) {
  for (const Entry& e : entries_)
    if (e.target == path) fail("%s: written twice in one set", path.c_str());
  if (entries_.empty() && lock_fd_ < 0) lock_fd_ = lock_folder(path.parent_path(), true);
  fs::path tmp = write_temporary(path, bytes);  // on failure the destructor removes the earlier ones
  entries_.push_back({path, std::move(tmp)});
  save_step();
}

void FileSet::add(const fs::path& path, const std::string& text) { add(path, text_bytes(text)); }

void FileSet::commit() {
  // Every file is on disk under its temporary name and no target is a folder: the journal, then the renames (same
  // folder, same file system) are what remains.
  std::vector<Entry> pending = std::move(entries_);
  entries_.clear();
  struct Unlock {
    int& fd;
    ~Unlock() { unlock_folder(fd); }
  } unlock{lock_fd_};
  if (pending.empty()) return;
  const fs::path folder = pending.front().target.parent_path();
  const fs::path journal = folder / kFileSetJournal;
  std::string text = "cumulo-file-set 1\n";
  for (const Entry& e : pending) text += fs::absolute(e.temp).string() + "\t" + fs::absolute(e.target).string() + "\n";
  try {
    write_file_atomic(journal, text);
  } catch (const Error&) {
    std::error_code ec;
    for (const Entry& e : pending) fs::remove(e.temp, ec);
    throw;
  }
  sync_folder(folder);
  save_step();
  for (size_t i = 0; i < pending.size(); ++i) {
    std::error_code ec;
    fs::rename(pending[i].temp, pending[i].target, ec);
    if (ec) {
      // Not a crash: undo what can be undone (the renamed files stay new; the journal goes, so the temporaries left
      // are removed too and nothing later takes this half set for a committed one).
      const std::string why = ec.message();
      for (size_t j = i; j < pending.size(); ++j) fs::remove(pending[j].temp, ec);
      fs::remove(journal, ec);
      fail("%s: cannot replace: %s", pending[i].target.c_str(), why.c_str());
    }
    save_step();
  }
  for (const Entry& e : pending)
    if (e.target.parent_path() != folder) sync_folder(e.target.parent_path());
  sync_folder(folder);
  std::error_code ec;
  fs::remove(journal, ec);
  sync_folder(folder);
  save_step();
}

std::vector<std::string> recover_file_sets(const fs::path& folder) {
  std::vector<std::string> done;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return done;
  int lock = lock_folder(folder, false);
  if (lock == -1) return done;  // a save in progress in another process
  struct Unlock {
    int& fd;
    ~Unlock() { unlock_folder(fd); }
  } unlock{lock};
  const fs::path journal = folder / kFileSetJournal;
  if (fs::is_regular_file(journal, ec)) {
    std::istringstream in(read_file_text(journal));
    std::string line;
    if (!std::getline(in, line) || line != "cumulo-file-set 1")
      fail("%s: not a file-set journal (its first line is not \"cumulo-file-set 1\")", journal.c_str());
    for (int n = 2; std::getline(in, line); ++n) {
      const size_t tab = line.find('\t');
      if (tab == std::string::npos) fail("%s:%d: expected TEMPORARY<tab>TARGET", journal.c_str(), n);
      const fs::path temp = line.substr(0, tab), target = line.substr(tab + 1);
      if (!fs::exists(temp, ec)) continue;  // renamed before the process stopped
      fs::rename(temp, target, ec);
      if (ec) fail("%s:%d: cannot finish the rename of %s: %s", journal.c_str(), n, target.c_str(), ec.message().c_str());
      done.push_back("finished an interrupted save: " + target.string());
    }
    sync_folder(folder);
    fs::remove(journal, ec);
    sync_folder(folder);
  }
  // Temporaries no journal names: a set killed before it committed (or a single write killed midway).
  fs::directory_iterator it(folder, ec);
  if (ec) return done;
  std::vector<fs::path> leftovers;
  for (const fs::directory_entry& e : it)
    if (e.path().extension() == ".tmp" && e.is_regular_file(ec)) leftovers.push_back(e.path());
  for (const fs::path& p : leftovers)
    if (fs::remove(p, ec)) done.push_back("removed the temporary file of an interrupted save: " + p.string());
  return done;
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
