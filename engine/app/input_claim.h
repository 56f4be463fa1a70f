#pragma once
// A module's UI takes input before the engine (keys typed into a text field, a drag over a panel): what
// it claims, the fly camera and the run loop's own keys (Esc quits, Tab captures the cursor) never see.
#include "engine/platform/input.h"

namespace cumulo::app {

struct InputClaim {
  bool keyboard = false, mouse = false;
};

// `input` without what `claim` took: no key down or pressed for a keyboard claim; no buttons, motion or
// wheel for a mouse claim. The cursor position and capture state stay (they are not events).
platform::InputState unclaimed_input(const platform::InputState& input, const InputClaim& claim);

}  // namespace cumulo::app
