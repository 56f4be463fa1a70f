#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "tests/support/temp_dir.h"

using namespace cumulo;
namespace fs = std::filesystem;

TEST(FileIo, AtomicWriteReplacesAndLeavesNoTemp) {
  fs::path dir = cumulo::test::unique_temp_path("cumulo_file_io_test");
  fs::remove_all(dir);
  fs::path p = dir / "a.json";
  write_file_atomic(p, std::string("one"));
  write_file_atomic(p, std::string("two"));
  EXPECT_EQ(read_file_text(p), "two");
  EXPECT_FALSE(fs::exists(dir / "a.json.tmp"));
  fs::remove_all(dir);
}

TEST(FileIo, MissingFileNamesPath) {
  try {
    read_file_bytes("/nonexistent/cumulo/x.bin");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cumulo/x.bin"), std::string::npos);
  }
}

TEST(FileIo, AtomicWriteIntoImpossibleFolderIsCumuloError) {
  EXPECT_THROW(write_file_atomic("/proc/cumulo/nope/a.txt", std::string("x")), Error);
}

TEST(FileIo, RepoRootIsTheSourceTreeNotTheBuildFolder) {
  // CTest sets CUMULO_ROOT; without it the search must still skip build/ (which has shaders/ and content/).
  const char* saved = std::getenv("CUMULO_ROOT");
  std::string keep = saved ? saved : "";
  unsetenv("CUMULO_ROOT");
  fs::path root = repo_root();
  if (saved) setenv("CUMULO_ROOT", keep.c_str(), 1);
  EXPECT_TRUE(fs::exists(root / "shaders" / "CMakeLists.txt")) << root;
  EXPECT_TRUE(fs::exists(root / "content" / "levels")) << root;
}
