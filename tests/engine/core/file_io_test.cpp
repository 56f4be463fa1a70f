#include <gtest/gtest.h>

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
