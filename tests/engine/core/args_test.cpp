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

namespace {
std::string parse_error(ArgParser& p, std::vector<const char*> argv) {
  argv.insert(argv.begin(), "cmd");
  try {
    p.parse(int(argv.size()), const_cast<char**>(argv.data()));
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}
}  // namespace

TEST(Args, NumbersFollowTheOutsideNumberRule) {
  int i = 0;
  uint32_t u = 0;
  uint64_t u64 = 0;
  float f = 0;
  double d = 0;
  ArgParser p("cmd", "");
  p.option("--i", "N", "", &i).option("--u", "N", "", &u).option("--u64", "N", "", &u64);
  p.option("--f", "X", "", &f).option("--d", "X", "", &d);
  // An integer flag given 4294967312 used to wrap to 16.
  EXPECT_NE(parse_error(p, {"--i", "4294967312"}).find("--i: 4294967312 does not fit a 32-bit integer"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--u", "4294967312"}).find("--u: 4294967312 does not fit"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--u64", "-1"}).find("--u64: -1 does not fit"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--u64", "99999999999999999999"}).find("does not fit"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--f", "nan"}).find("--f: expected a finite number, got nan"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--f", "1e39"}).find("--f: 1e+39 does not fit a 32-bit float"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--d", "inf"}).find("--d: expected a finite number"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--d", "1e999"}).find("--d: expected a finite number"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--i", " 5"}).find("expected an integer"), std::string::npos);
  EXPECT_EQ(parse_error(p, {"--i", "-5", "--u", "4294967295", "--u64", "18446744073709551615", "--f", "3e38", "--d", "1e300"}),
            "(accepted)");
  EXPECT_EQ(i, -5);
  EXPECT_EQ(u, 4294967295u);
  EXPECT_EQ(u64, 18446744073709551615ull);
  EXPECT_FLOAT_EQ(f, 3e38f);
  EXPECT_DOUBLE_EQ(d, 1e300);
}

TEST(Args, RangesAreCheckedAndShownInHelp) {
  float voxel = 0;
  double start = 0;
  ArgParser p("cmd", "");
  p.option("--voxel-size", "M", "voxel", &voxel).range(0.0, 1024.0, Open::Low);
  p.option("--start-at", "S", "start", &start).range(0.0, 100.0);
  EXPECT_NE(parse_error(p, {"--voxel-size", "0"}).find("--voxel-size: 0 is out of range (expected 0 < x <= 1024)"),
            std::string::npos);
  EXPECT_NE(parse_error(p, {"--voxel-size", "-3"}).find("out of range"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--start-at", "nan"}).find("--start-at: expected a finite number"), std::string::npos);
  EXPECT_NE(parse_error(p, {"--start-at", "100.5"}).find("expected 0..100"), std::string::npos);
  EXPECT_EQ(parse_error(p, {"--voxel-size", "1024", "--start-at", "0"}), "(accepted)");
  EXPECT_NE(p.help().find("[0 < x <= 1024]"), std::string::npos) << p.help();
}

TEST(Args, ListsAndEchoedValues) {
  EXPECT_EQ(parse_flag_list<float>("--origin", "1,-2.5,3", 3), (std::vector<float>{1.0f, -2.5f, 3.0f}));
  EXPECT_THROW(parse_flag_list<float>("--origin", "nan,0,0", 3), Error);
  EXPECT_THROW(parse_flag_list<float>("--origin", "1,2", 3), Error);
  EXPECT_THROW(parse_flag_list<float>("--origin", "1,2,3,4", 3), Error);
  EXPECT_THROW(parse_flag_list<uint32_t>("--dims", "1,2,4294967312", 3), Error);
  std::string big(2 << 20, '7');
  try {
    parse_flag_number<float>("--f", big + "x");
    FAIL();
  } catch (const Error& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
  }
}
