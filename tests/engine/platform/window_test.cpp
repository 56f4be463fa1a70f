// Window tests need a display: they run under Xvfb (xvfb-run) and are skipped without one.
#include "engine/platform/window.h"

#include <cstdlib>

#include <gtest/gtest.h>

#include "engine/core/error.h"

using namespace cumulo;
using namespace cumulo::platform;

TEST(Window, DisplayAvailableFollowsTheEnvironment) {
  const char* saved = std::getenv("DISPLAY");
  std::string keep = saved ? saved : "";
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  std::string keep_wl = wl ? wl : "";
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  EXPECT_FALSE(display_available());
  setenv("DISPLAY", ":99", 1);
  EXPECT_TRUE(display_available());
  if (saved) setenv("DISPLAY", keep.c_str(), 1); else unsetenv("DISPLAY");
  if (wl) setenv("WAYLAND_DISPLAY", keep_wl.c_str(), 1);
}

TEST(Window, BadDisplayIsAnErrorNotACrash) {
  const char* saved = std::getenv("DISPLAY");
  std::string keep = saved ? saved : "";
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  std::string keep_wl = wl ? wl : "";
  unsetenv("WAYLAND_DISPLAY");
  setenv("DISPLAY", ":987", 1);  // nothing listens there
  EXPECT_THROW(Window::create({"cumulo test", 64, 64}), Error);
  if (saved) setenv("DISPLAY", keep.c_str(), 1); else unsetenv("DISPLAY");
  if (wl) setenv("WAYLAND_DISPLAY", keep_wl.c_str(), 1);
}

TEST(Window, OpensPollsAndCloses) {
  if (!display_available()) GTEST_SKIP() << "no display (run under xvfb-run)";
  auto w = Window::create({"cumulo test", 160, 90});
  InputState in;
  w->poll(in);
  EXPECT_FALSE(w->should_close());
  EXPECT_GT(w->width(), 0u);
  EXPECT_FALSE(Window::required_vulkan_extensions().empty());
  w->request_close();
  EXPECT_TRUE(w->should_close());
}
