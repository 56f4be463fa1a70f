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

TEST(FileIo, DevicesAreNotReadAsFiles) {
  // /dev/zero has no end: reading it grew memory until std::bad_alloc.
  try {
    read_file_bytes("/dev/zero");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/dev/zero: not a regular file");
  }
  EXPECT_THROW(read_file_bytes(std::filesystem::temp_directory_path()), Error);
}

TEST(FileIo, FileSetReplacesAllOrNothing) {
  namespace fs = std::filesystem;
  const fs::path dir = cumulo::test::unique_temp_path("cumulo_file_set");
  fs::remove_all(dir);
  {
    FileSet s;
    s.add(dir / "a.txt", std::string("a1"));
    s.add(dir / "b.txt", std::string("b1"));
    EXPECT_FALSE(fs::exists(dir / "a.txt"));  // nothing in place before commit
    s.commit();
  }
  EXPECT_EQ(read_file_text(dir / "a.txt"), "a1");
  EXPECT_EQ(read_file_text(dir / "b.txt"), "b1");
  fs::create_directories(dir / "c.txt");  // cannot be replaced
  {
    FileSet s;
    s.add(dir / "a.txt", std::string("a2"));
    s.add(dir / "b.txt", std::string("b2"));
    try {
      s.add(dir / "c.txt", std::string("c2"));
      FAIL();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("c.txt: cannot replace: it is a folder"), std::string::npos) << e.what();
    }
  }  // never committed: the temporaries go
  EXPECT_EQ(read_file_text(dir / "a.txt"), "a1");
  EXPECT_EQ(read_file_text(dir / "b.txt"), "b1");
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  // write_file_atomic onto a folder leaves no temporary either.
  EXPECT_THROW(write_file_atomic(dir / "c.txt", std::string("x")), Error);
  EXPECT_FALSE(fs::exists(dir / "c.txt.tmp"));
  fs::remove_all(dir);
}
