#pragma once
// Input as plain data: the window fills an InputState once per frame (poll), the app loop hands a copy
// to whoever needs it (camera controller, later the editor). Headless runs keep an all-zero state.
#include <array>
#include <cstddef>
#include <cstdint>

namespace cumulo::platform {

enum class Key : uint8_t { W, A, S, D, Q, E, Space, LeftShift, LeftControl, Escape, Tab, F1, R, Count };
enum class MouseButton : uint8_t { Left, Right, Middle, Count };

struct InputState {
  std::array<bool, static_cast<size_t>(Key::Count)> down{};     // held this frame
  std::array<bool, static_cast<size_t>(Key::Count)> pressed{};  // went down since the last poll
  std::array<bool, static_cast<size_t>(MouseButton::Count)> mouse_down{};
  double mouse_x = 0, mouse_y = 0;    // cursor position in window pixels
  double mouse_dx = 0, mouse_dy = 0;  // motion since the last poll (pixels; unbounded when captured)
  double scroll = 0;                  // wheel steps since the last poll
  bool cursor_captured = false;

  bool is_down(Key k) const { return down[static_cast<size_t>(k)]; }
  bool was_pressed(Key k) const { return pressed[static_cast<size_t>(k)]; }
  bool is_down(MouseButton b) const { return mouse_down[static_cast<size_t>(b)]; }
};

const char* key_name(Key k);

}  // namespace cumulo::platform
