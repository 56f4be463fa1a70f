#include "engine/app/input_claim.h"

namespace cumulo::app {

platform::InputState unclaimed_input(const platform::InputState& input, const InputClaim& claim) {
  platform::InputState out = input;
  if (claim.keyboard) out.down = out.pressed = {};
  if (claim.mouse) {
    out.mouse_down = {};
    out.mouse_dx = out.mouse_dy = out.scroll = 0.0;
  }
  return out;
}

}  // namespace cumulo::app
