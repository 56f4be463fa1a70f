#include <gtest/gtest.h>

#include "engine/core/error.h"
#include "engine/core/message.h"

using namespace cumulo;

TEST(Message, QuoteCutsLongValuesAndKeepsOneLine) {
  EXPECT_EQ(quote("abc"), "\"abc\"");
  EXPECT_EQ(quote("a\nb\tc"), "\"a\\nb\\tc\"");
  EXPECT_EQ(quote("abcdef", 3), "\"abc\"... (6 bytes)");
  EXPECT_EQ(clip("abcdef", 3), "abc... (6 bytes)");
  std::string big(2 << 20, 'y');
  EXPECT_LT(quote(big).size(), 120u);
}

TEST(Message, LibraryMessagesLoseTheirPrefixes) {
  EXPECT_EQ(library_message("[json.exception.out_of_range.406] number overflow parsing '1e999999'"),
            "number overflow parsing '1e999999'");
  EXPECT_EQ(library_message("IoError: could not open file"), "could not open file");
  EXPECT_EQ(library_message("RuntimeError: ValueError: bad grid\n"), "bad grid");
  EXPECT_EQ(library_message("first\nsecond\n"), "first; second");
  EXPECT_LE(library_message(std::string(100000, 'z')).size(), 340u);
}
