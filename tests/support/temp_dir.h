#pragma once
// Temporary folders for tests: the one helper every test uses. CTest runs the tests of one binary as
// separate processes in parallel (-j), so a fixed folder name lets two tests delete each other's files;
// the pid keeps them apart, and test_temp_name() gives each test of a process its own folder.
//
//   fs::path p = unique_temp_path("cumulo_x");                   // a name only: nothing created
//   fs::path d = fresh_temp_dir("cumulo_x");                     // emptied and created
//   fs::path t = fresh_temp_dir(test_temp_name("cumulo_scene")); // one per running GoogleTest test
//   TempDir tmp("cumulo_x");                                     // fresh_temp_dir, removed at scope exit
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace cumulo::test {

// <system temp>/<name>_<pid>, neither created nor removed.
inline std::filesystem::path unique_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

// unique_temp_path(name), emptied of what an earlier run left and created.
inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  const std::filesystem::path dir = unique_temp_path(name);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  std::filesystem::create_directories(dir);
  return dir;
}

// prefix_<suite>_<test> of the running GoogleTest test (prefix alone outside a test).
inline std::string test_temp_name(const std::string& prefix) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (!info) return prefix;
  return prefix + "_" + info->test_suite_name() + "_" + info->name();
}

// A fresh folder removed at scope exit. Declare it before anything that writes into it when destroyed
// (a gpu::Context writes its pipeline cache then).
class TempDir {
 public:
  explicit TempDir(const std::string& name) : path(fresh_temp_dir(name)) {}
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path path;
};

}  // namespace cumulo::test
