#include <gtest/gtest.h>

#include <cmath>

#include "engine/core/error.h"
#include "engine/core/number.h"

using namespace cumulo;

TEST(Number, OneRuleForOutsideNumbers) {
  EXPECT_FALSE(number_problem<float>(3.0e38));
  EXPECT_TRUE(number_problem<float>(1.0e39));
  EXPECT_TRUE(number_problem<float>(std::nan("")));
  EXPECT_TRUE(number_problem<double>(INFINITY));
  EXPECT_FALSE(number_problem<double>(1.0e300));
  EXPECT_FALSE(number_problem<int>(-2147483648.0));
  EXPECT_TRUE(number_problem<int>(2147483648.0));
  EXPECT_TRUE(number_problem<int>(1.5));
  EXPECT_TRUE(number_problem<uint32_t>(-1.0));
  EXPECT_FALSE(number_problem<uint32_t>(4294967295.0));
  EXPECT_TRUE(number_problem<uint32_t>(4294967296.0));
  EXPECT_TRUE(number_problem<int64_t>(9223372036854775808.0));  // 2^63: one past the top
  EXPECT_FALSE(integer_problem<uint64_t>(uint64_t(-1)));
  EXPECT_TRUE(integer_problem<int64_t>(uint64_t(-1)));
  EXPECT_TRUE(integer_problem<uint32_t>(int64_t(4294967312)));
  EXPECT_EQ(*number_problem<float>(1e39), "1e+39 does not fit a 32-bit float (|x| <= 3.40282e+38)");
  EXPECT_THROW(narrow_number<float>(1e39, [](const std::string& why) { throw Error(why); }), Error);
  EXPECT_EQ(narrow_number<int>(7.0, [](const std::string& why) { throw Error(why); }), 7);
}
