// The editor's disk watch: a thread that notices files added, rewritten or removed.
#include "editor/model/folder_watch.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "tests/support/temp_dir.h"

namespace fs = std::filesystem;
using cumulo::editor::FolderWatch;

namespace {

// Waits for the watch to see a change (it looks every 10 ms here); false after 2 s.
bool sees_change(FolderWatch& w) {
  for (int i = 0; i < 200; ++i) {
    if (w.changed()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace

TEST(FolderWatch, NoticesAFileAddedRewrittenAndRemovedAndNothingElse) {
  cumulo::test::TempDir tmp(cumulo::test::test_temp_name("cumulo_folder_watch"));
  FolderWatch w(tmp.path, std::chrono::milliseconds(10));
  EXPECT_TRUE(w.changed()) << "the first call reports the folder as new";
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(w.changed()) << "nothing happened";
  std::ofstream(tmp.path / "a.json") << "{}";
  EXPECT_TRUE(sees_change(w));
  EXPECT_FALSE(w.changed()) << "a change is reported once";
  std::ofstream(tmp.path / "a.json") << "{\"coverage\": 1}";
  EXPECT_TRUE(sees_change(w));
  fs::remove(tmp.path / "a.json");
  EXPECT_TRUE(sees_change(w));
  EXPECT_EQ(FolderWatch::fingerprint(tmp.path / "missing"), 0u);
}
