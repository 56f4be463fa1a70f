#include "engine/render/budget_mode.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"

using namespace cumulo;
using namespace cumulo::render;

TEST(BudgetMode, ParsesTheThreeModes) {
  EXPECT_EQ(parse_budget_mode("30"), BudgetMode::Hz30);
  EXPECT_EQ(parse_budget_mode("40"), BudgetMode::Hz40);
  EXPECT_EQ(parse_budget_mode("60Hz"), BudgetMode::Hz60);
  EXPECT_EQ(budget_hz(BudgetMode::Hz40), 40);
  EXPECT_DOUBLE_EQ(budget_frame_seconds(BudgetMode::Hz30), 1.0 / 30.0);
  EXPECT_STREQ(budget_mode_name(BudgetMode::Hz60), "60 Hz");
}

TEST(BudgetMode, RejectsOtherRatesWithTheAcceptedValues) {
  try {
    parse_budget_mode("45");
    FAIL() << "45 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("30, 40 or 60"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_budget_mode(""), Error);
}
