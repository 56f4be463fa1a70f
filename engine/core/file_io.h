#pragma once
// Whole-file IO. Errors throw cumulo::Error naming the path and the OS reason.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace cumulo {

// Regular files only (not devices or pipes), at most kMaxReadBytes.
inline constexpr uint64_t kMaxReadBytes = 16ull << 30;
std::vector<uint8_t> read_file_bytes(const std::filesystem::path& path);
std::string read_file_text(const std::filesystem::path& path);

// Atomic save: writes PATH.tmp, flushes it to disk, then renames over PATH, so a failed save never
// loses the last good file.
void write_file_atomic(const std::filesystem::path& path, std::span<const uint8_t> bytes);
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

// Several files written as one set (a bake's or an import's outputs, the editor's save): add() writes each to a
// temporary name beside its target (PATH.tmp, flushed to disk); commit() writes a journal naming every rename
// (FOLDER/.cumulo-commit, FOLDER the first target's; flushed, then renamed into place: the commit point), renames
// them all into place and removes the journal. A process killed at any step leaves either the old set with some
// temporaries (no journal: the set never committed) or a journal; recover_file_sets() on the folder then finishes
// the renames or removes the temporaries, so a reader sees the whole old set or the whole new one, never a mix.
// A failed add() or a set never committed removes its temporaries and leaves the previous files exactly as they
// were. Targets that cannot be replaced (a folder) are refused by add(), before any file of the set is renamed.
//
//   FileSet set;
//   set.add(dir / "field.nvdf", bytes);   // throws "FILE: ..." naming the file
//   set.add(dir / "bake_report.json", text);
//   set.commit();
//
// Tests stop a process at a step of its writes with CUMULO_KILL_AT_SAVE_STEP=N: the N-th step (1-based; a
// temporary written, the journal written, a file renamed, the journal removed) sends it SIGKILL.
class FileSet {
 public:
  FileSet() = default;
  FileSet(const FileSet&) = delete;
  FileSet& operator=(const FileSet&) = delete;
  ~FileSet();  // removes temporaries not committed

  void add(const std::filesystem::path& path, std::span<const uint8_t> bytes);
  void add(const std::filesystem::path& path, const std::string& text);
  void commit();

 private:
  struct Entry {
    std::filesystem::path target, temp;
  };
  std::vector<Entry> entries_;
  int lock_fd_ = -1;  // the first target's folder's lock (in the cache folder), from the first add() to the end of commit()
};

// Finishes or undoes a file set that a killed process left in `folder`: with a journal there, the renames it names
// whose temporaries remain are done (the set had committed); without one, leftover temporaries (*.tmp) are removed
// (it had not). A save in progress (another process holds the folder's lock) is left alone. Returns what it did, one line per action (empty: the folder was clean). Throws cumulo::Error naming
// the journal when it cannot be read or a rename fails.
std::vector<std::string> recover_file_sets(const std::filesystem::path& folder);
inline constexpr const char* kFileSetJournal = ".cumulo-commit";

// The repository root: $CUMULO_ROOT if set, else the nearest parent of the executable or of the
// working directory that holds shaders/CMakeLists.txt and content/levels/ (a build folder has
// shaders/ and content/ too, so those alone are not enough).
std::filesystem::path repo_root();

}  // namespace cumulo
