#pragma once
// A per-process temporary path for tests. CTest runs the tests of one binary as separate processes in
// parallel (-j), so a fixed folder name lets two tests delete each other's files; the pid keeps them apart.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace cumulo::test {

inline std::filesystem::path unique_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

}  // namespace cumulo::test
