#pragma once
// Whole-file IO. Errors throw cumulo::Error naming the path and the OS reason.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace cumulo {

std::vector<uint8_t> read_file_bytes(const std::filesystem::path& path);
std::string read_file_text(const std::filesystem::path& path);

// Atomic save: writes PATH.tmp, flushes it to disk, then renames over PATH, so a failed save never
// loses the last good file.
void write_file_atomic(const std::filesystem::path& path, std::span<const uint8_t> bytes);
void write_file_atomic(const std::filesystem::path& path, const std::string& text);

// The repository root: $CUMULO_ROOT if set, else the nearest parent of the executable or of the
// working directory that holds shaders/CMakeLists.txt and content/levels/ (a build folder has
// shaders/ and content/ too, so those alone are not enough).
std::filesystem::path repo_root();

}  // namespace cumulo
