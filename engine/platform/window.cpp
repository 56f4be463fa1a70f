#include "engine/platform/window.h"

#include <cstdlib>
#include <mutex>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "engine/core/error.h"
#include "engine/core/log.h"

namespace cumulo::platform {
namespace {

// GLFW is process-global: initialize once, terminate with the last window.
int g_windows = 0;
std::string g_last_glfw_error;

void on_glfw_error(int code, const char* description) {
  g_last_glfw_error = strf("GLFW error %d: %s", code, description ? description : "?");
  LOG_DEBUG("%s", g_last_glfw_error.c_str());
}

void glfw_acquire() {
  if (g_windows++ > 0) return;
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) {
    g_windows = 0;
    fail("cannot initialize the window system (%s)", g_last_glfw_error.empty() ? "no display?" : g_last_glfw_error.c_str());
  }
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    g_windows = 0;
    fail("the window system has no Vulkan support (GLFW found no Vulkan loader)");
  }
}

void glfw_release() {
  if (--g_windows == 0) glfwTerminate();
}

constexpr int kGlfwKeys[] = {GLFW_KEY_W,     GLFW_KEY_A,          GLFW_KEY_S,            GLFW_KEY_D,      GLFW_KEY_Q,
                             GLFW_KEY_E,     GLFW_KEY_SPACE,      GLFW_KEY_LEFT_SHIFT,   GLFW_KEY_LEFT_CONTROL,
                             GLFW_KEY_ESCAPE, GLFW_KEY_TAB,       GLFW_KEY_F1,           GLFW_KEY_R};
static_assert(sizeof(kGlfwKeys) / sizeof(kGlfwKeys[0]) == static_cast<size_t>(Key::Count));

}  // namespace

const char* key_name(Key k) {
  static const char* names[] = {"W", "A", "S", "D", "Q", "E", "Space", "LeftShift", "LeftControl", "Escape", "Tab", "F1", "R"};
  static_assert(sizeof(names) / sizeof(names[0]) == static_cast<size_t>(Key::Count));
  return names[static_cast<size_t>(k)];
}

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* w = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (w && *w);
}

std::unique_ptr<Window> Window::create(const WindowDesc& desc) {
  glfw_acquire();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, desc.resizable ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* w = glfwCreateWindow(static_cast<int>(desc.width), static_cast<int>(desc.height), desc.title.c_str(), nullptr, nullptr);
  if (!w) {
    glfw_release();
    fail("cannot open a %ux%u window (%s)", desc.width, desc.height, g_last_glfw_error.c_str());
  }
  std::unique_ptr<Window> win(new Window());
  win->window_ = w;
  glfwSetWindowUserPointer(w, win.get());
  glfwSetFramebufferSizeCallback(w, [](GLFWwindow* gw, int, int) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->resized_ = true;
  });
  glfwSetScrollCallback(w, [](GLFWwindow* gw, double, double dy) {
    static_cast<Window*>(glfwGetWindowUserPointer(gw))->scroll_ += dy;
  });
  return win;
}

Window::~Window() {
  if (window_) {
    glfwDestroyWindow(window_);
    glfw_release();
  }
}

std::vector<const char*> Window::required_vulkan_extensions() {
  glfw_acquire();
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  std::vector<const char*> out(names, names + count);
  glfw_release();
  if (out.empty()) fail("GLFW reports no Vulkan surface extensions (%s)", g_last_glfw_error.c_str());
  return out;
}

VkSurfaceKHR Window::create_surface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
  if (r != VK_SUCCESS) fail("cannot create a Vulkan surface for the window (VkResult %d, %s)", r, g_last_glfw_error.c_str());
  return surface;
}

void Window::poll(InputState& input) {
  glfwPollEvents();
  for (size_t i = 0; i < static_cast<size_t>(Key::Count); ++i) {
    bool d = glfwGetKey(window_, kGlfwKeys[i]) == GLFW_PRESS;
    input.down[i] = d;
    input.pressed[i] = d && !prev_down_[i];
    prev_down_[i] = d;
  }
  input.mouse_down[0] = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  input.mouse_down[1] = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  input.mouse_down[2] = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  if (first_mouse_) {
    last_x_ = x;
    last_y_ = y;
    first_mouse_ = false;
  }
  input.mouse_dx = x - last_x_;
  input.mouse_dy = y - last_y_;
  input.mouse_x = x;
  input.mouse_y = y;
  last_x_ = x;
  last_y_ = y;
  input.scroll = scroll_;
  scroll_ = 0;
  input.cursor_captured = captured_;
}

bool Window::should_close() const { return glfwWindowShouldClose(window_); }
void Window::request_close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void Window::cancel_close() { glfwSetWindowShouldClose(window_, GLFW_FALSE); }

uint32_t Window::width() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return static_cast<uint32_t>(w);
}
uint32_t Window::height() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return static_cast<uint32_t>(h);
}

bool Window::consume_resized() {
  bool r = resized_;
  resized_ = false;
  return r;
}

void Window::wait_while_minimized() {
  while ((width() == 0 || height() == 0) && !should_close()) glfwWaitEventsTimeout(0.1);
}

void Window::set_cursor_captured(bool captured) {
  if (captured == captured_) return;
  captured_ = captured;
  glfwSetInputMode(window_, GLFW_CURSOR, captured ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
  if (captured && glfwRawMouseMotionSupported()) glfwSetInputMode(window_, GLFW_RAW_MOUSE_MOTION, GLFW_TRUE);
  first_mouse_ = true;  // avoid a jump from the old cursor position
}

void Window::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

}  // namespace cumulo::platform
