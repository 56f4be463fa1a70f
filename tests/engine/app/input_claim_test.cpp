// What a module's UI claims never reaches the fly camera or the run loop's keys (issue 12: keys typed
// into a text field never move the camera; Esc leaves a text field before it asks to quit).
#include "engine/app/input_claim.h"

#include <gtest/gtest.h>

#include "engine/app/fly_camera.h"

using namespace cumulo::app;
using cumulo::platform::InputState;
using cumulo::platform::Key;
using cumulo::platform::MouseButton;

namespace {

InputState typing_w_and_escape_while_dragging() {
  InputState in;
  in.down[size_t(Key::W)] = in.pressed[size_t(Key::W)] = true;
  in.down[size_t(Key::Escape)] = in.pressed[size_t(Key::Escape)] = true;
  in.mouse_down[size_t(MouseButton::Right)] = true;
  in.mouse_dx = 40.0;
  in.scroll = 1.0;
  return in;
}

}  // namespace

TEST(InputClaim, KeysTypedIntoATextFieldNeitherMoveTheCameraNorQuit) {
  const InputState in = typing_w_and_escape_while_dragging();
  const InputState own = unclaimed_input(in, {.keyboard = true, .mouse = false});
  EXPECT_FALSE(own.was_pressed(Key::Escape));  // the text field takes Esc: the loop does not ask to quit
  FlyCamera c;
  const glm::vec3 before = c.position;
  update_fly_camera(c, unclaimed_input(in, {.keyboard = true, .mouse = true}), 0.5f);
  EXPECT_EQ(c.position, before);
  // Unclaimed, the same input moves the camera and Esc reaches the loop.
  FlyCamera free;
  update_fly_camera(free, in, 0.5f);
  EXPECT_NE(free.position, before);
  EXPECT_TRUE(unclaimed_input(in, {}).was_pressed(Key::Escape));
}

TEST(InputClaim, AMouseClaimKeepsTheKeysAndDropsTheDrag) {
  const InputState in = typing_w_and_escape_while_dragging();
  const InputState own = unclaimed_input(in, {.keyboard = false, .mouse = true});
  EXPECT_TRUE(own.is_down(Key::W));
  EXPECT_FALSE(own.is_down(MouseButton::Right));
  EXPECT_EQ(own.mouse_dx, 0.0);
  EXPECT_EQ(own.scroll, 0.0);
  EXPECT_EQ(own.mouse_x, in.mouse_x);
}
