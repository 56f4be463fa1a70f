#pragma once
// The GLFW window (DESIGN.md engine/platform). Headless runs never construct one and never call
// glfwInit, so they work with no display at all.
//
//   if (platform::display_available()) window = platform::Window::create({"cumulo", 1280, 720});
//   while (!window->should_close()) { window->poll(input); ... }
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/platform/input.h"

struct GLFWwindow;

namespace cumulo::platform {

struct WindowDesc {
  std::string title = "cumulo";
  uint32_t width = 1280, height = 720;
  bool resizable = true;
};

// True when an X11 or Wayland display is named in the environment. glfwInit can still fail (a dead
// display); Window::create reports that as a cumulo::Error so the caller can fall back to headless.
bool display_available();

class Window {
 public:
  // Initializes GLFW on first use (no OpenGL context: GLFW_NO_API) and opens the window.
  // Throws cumulo::Error with GLFW's own description when that fails.
  static std::unique_ptr<Window> create(const WindowDesc& desc);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Instance extensions needed to present to this platform's windows (VK_KHR_surface + the WSI one).
  static std::vector<const char*> required_vulkan_extensions();
  // Creates a VkSurfaceKHR for this window; throws cumulo::Error on failure.
  VkSurfaceKHR create_surface(VkInstance instance) const;

  // Pumps events and fills `input` (pressed/deltas are since the previous poll). Escape is the run
  // loop's to act on (a UI's text field takes it first).
  void poll(InputState& input);
  bool should_close() const;
  void request_close();
  void cancel_close();  // the close was refused (unsaved changes): keep running

  // Framebuffer size in pixels (0x0 while minimized).
  uint32_t width() const;
  uint32_t height() const;
  // True once after the framebuffer size changed (the swapchain must be recreated).
  bool consume_resized();
  // Blocks while minimized (0x0 framebuffer) unless close was requested.
  void wait_while_minimized();

  void set_cursor_captured(bool captured);
  void set_title(const std::string& title);
  GLFWwindow* handle() const { return window_; }

 private:
  Window() = default;
  GLFWwindow* window_ = nullptr;
  bool resized_ = false;
  bool captured_ = false;
  bool first_mouse_ = true;
  double last_x_ = 0, last_y_ = 0, scroll_ = 0;
  std::array<bool, static_cast<size_t>(Key::Count)> prev_down_{};
};

}  // namespace cumulo::platform
