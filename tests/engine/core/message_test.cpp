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

// Every error is bounded where it is made: a 2 MB value echoed by a site that did not quote it comes back cut in its
// middle with its length, the words around it whole; a short message is unchanged; a message of many short words is
// cut after kMaxMessageBytes.
TEST(Message, EveryErrorIsBounded) {
  const std::string path = "/levels/" + std::string(2000000, 'x') + ".glb";
  try {
    fail("level.json: $.entities[0].components.ModelRef.path: model file not found: %s", path.c_str());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_LT(m.size(), 1000u);
    EXPECT_EQ(m.rfind("level.json: $.entities[0].components.ModelRef.path: model file not found: /levels/xxx", 0), 0u) << m;
    EXPECT_NE(m.find("xxx.glb (2000012 bytes)"), std::string::npos) << m;
  }
  EXPECT_STREQ(Error("short: message").what(), "short: message");
  std::string words;
  for (int i = 0; i < 5000; ++i) words += "word ";
  const std::string cut = Error(words).what();
  EXPECT_LT(cut.size(), kMaxMessageBytes + 100);
  EXPECT_NE(cut.find("(message cut: 25000 bytes)"), std::string::npos);
}
