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

// Several files written as one set (a bake's or an import's outputs): add() writes each to a
// temporary name beside its target (PATH.tmp, flushed to disk), commit() renames them all into
// place once every write succeeded. A failed add() or a set never committed removes its temporaries
// and leaves the previous files exactly as they were. Targets that cannot be replaced (a folder)
// are refused by add(), before any file of the set is renamed.
//
//   FileSet set;
//   set.add(dir / "field.nvdf", bytes);   // throws "FILE: ..." naming the file
//   set.add(dir / "bake_report.json", text);
//   set.commit();
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
};

// The repository root: $CUMULO_ROOT if set, else the nearest parent of the executable or of the
// working directory that holds shaders/CMakeLists.txt and content/levels/ (a build folder has
// shaders/ and content/ too, so those alone are not enough).
std::filesystem::path repo_root();

}  // namespace cumulo
