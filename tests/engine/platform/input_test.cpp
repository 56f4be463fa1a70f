#include "engine/platform/input.h"

#include <gtest/gtest.h>

using namespace cumulo::platform;

TEST(Input, DefaultStateHasNothingDown) {
  InputState s;
  for (size_t i = 0; i < static_cast<size_t>(Key::Count); ++i) {
    EXPECT_FALSE(s.is_down(static_cast<Key>(i)));
    EXPECT_FALSE(s.was_pressed(static_cast<Key>(i)));
  }
  EXPECT_FALSE(s.is_down(MouseButton::Right));
  EXPECT_EQ(s.mouse_dx, 0.0);
}

TEST(Input, KeyNamesAreDistinct) {
  for (size_t i = 0; i < static_cast<size_t>(Key::Count); ++i)
    for (size_t j = i + 1; j < static_cast<size_t>(Key::Count); ++j)
      EXPECT_STRNE(key_name(static_cast<Key>(i)), key_name(static_cast<Key>(j)));
}
