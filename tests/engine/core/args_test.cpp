#include <gtest/gtest.h>

#include "engine/core/args.h"
#include "engine/core/error.h"

using namespace cumulo;

TEST(Args, ParsesOptionsFlagsAndPositionals) {
  std::string level, size;
  int frames = 0;
  float t = 0;
  bool headless = false;
  ArgParser p("cumulo run", "run");
  p.positional("LEVEL", "level", &level).option("--frames", "N", "", &frames).option("--size", "WxH", "", &size);
  p.option("--time-of-day", "H", "", &t).flag("--headless", "", &headless);
  const char* argv[] = {"run", "l.json", "--frames", "3", "--size=320x180", "--headless", "--time-of-day", "-1.5"};
  ASSERT_TRUE(p.parse(8, const_cast<char**>(argv)));
  EXPECT_EQ(level, "l.json");
  EXPECT_EQ(frames, 3);
  EXPECT_EQ(size, "320x180");
  EXPECT_TRUE(headless);
  EXPECT_FLOAT_EQ(t, -1.5f);
  EXPECT_TRUE(p.was_set("--frames"));
  EXPECT_FALSE(p.was_set("--stats"));
}

TEST(Args, RejectsBadInput) {
  int frames = 0;
  std::string level;
  ArgParser p("cumulo run", "run");
  p.positional("LEVEL", "level", &level).option("--frames", "N", "", &frames);
  const char* unknown[] = {"run", "x", "--bogus"};
  EXPECT_THROW(p.parse(3, const_cast<char**>(unknown)), Error);
  const char* bad_number[] = {"run", "x", "--frames", "three"};
  EXPECT_THROW(p.parse(4, const_cast<char**>(bad_number)), Error);
  const char* missing_value[] = {"run", "x", "--frames"};
  EXPECT_THROW(p.parse(3, const_cast<char**>(missing_value)), Error);
  const char* missing_pos[] = {"run"};
  EXPECT_THROW(p.parse(1, const_cast<char**>(missing_pos)), Error);
}
