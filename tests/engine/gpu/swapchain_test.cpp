// Presents to a real X11 window: run under Xvfb (CTest wraps this binary in xvfb-run when it is
// installed); skipped when no display is available.
#include <gtest/gtest.h>

#include <cstdlib>
#include <thread>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/swapchain.h"
#include "gpu_test_util.h"

using namespace cumulo::gpu;

namespace {

void render_frame(Context& ctx, FrameRing& frames, Swapchain& sc, float shade, VkExtent2D size) {
  Frame& f = frames.begin();
  std::optional<uint32_t> idx = sc.acquire(f.acquired);
  if (!idx) {
    frames.submit(f);  // nothing recorded; keeps the slot's fence cycle simple
    sc.recreate(size);
    return;
  }
  VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  // The acquire semaphore wait covers the presentation engine's read; COLOR_ATTACHMENT_OUTPUT | TRANSFER is the wait
  // stage.
  cmd_image_barrier(f.cmd, sc.image(*idx), range, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkClearColorValue c{{shade, 0.3f, 0.6f, 1.0f}};
  vkCmdClearColorImage(f.cmd, sc.image(*idx), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &c, 1, &range);
  cmd_image_barrier(f.cmd, sc.image(*idx), range, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, 0);
  sc.set_layout(*idx, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
  frames.submit(f, f.acquired, sc.render_finished(*idx), VK_PIPELINE_STAGE_2_TRANSFER_BIT);
  if (!sc.present(*idx)) sc.recreate(size);
}

}  // namespace

TEST(Swapchain, PresentsAndRecreatesOnResize) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) GTEST_SKIP() << "no DISPLAY (CTest runs this under xvfb-run when available)";
  ASSERT_TRUE(glfwInit());
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* win = glfwCreateWindow(64, 48, "cumulo gpu swapchain test", nullptr, nullptr);
  ASSERT_NE(win, nullptr);
  uint32_t before = total_validation_errors();
  cumulo::test::TempDir tmp("cumulo_gpu_swapchain");
  {
    uint32_t n = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&n);
    ContextDesc desc;
    desc.validation = true;
    desc.cache_dir = tmp.path;
    desc.instance_extensions.assign(exts, exts + n);
    desc.need_present = true;
    desc.create_surface = [&](VkInstance inst) {
      VkSurfaceKHR s = VK_NULL_HANDLE;
      if (glfwCreateWindowSurface(inst, win, nullptr, &s) != VK_SUCCESS) cumulo::fail("glfwCreateWindowSurface failed");
      return s;
    };
    Context ctx(desc);
    ASSERT_NE(ctx.surface(), VK_NULL_HANDLE);
    int w, h;
    glfwGetFramebufferSize(win, &w, &h);
    Swapchain sc(ctx, {uint32_t(w), uint32_t(h)});
    EXPECT_EQ(sc.extent().width, 64u);
    EXPECT_GE(sc.image_count(), 2u);
    FrameRing frames(ctx);
    for (int i = 0; i < 4; ++i) {
      glfwPollEvents();
      render_frame(ctx, frames, sc, float(i) / 4, {uint32_t(w), uint32_t(h)});
    }
    // Resize: the next present or acquire reports out-of-date / suboptimal, or we notice the size.
    glfwSetWindowSize(win, 96, 80);
    for (int tries = 0; tries < 100; ++tries) {
      glfwPollEvents();
      glfwGetFramebufferSize(win, &w, &h);
      if (w == 96 && h == 80) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_EQ(w, 96);
    uint32_t gen = sc.generation();
    if (sc.extent().width != uint32_t(w) || sc.extent().height != uint32_t(h)) sc.recreate({uint32_t(w), uint32_t(h)});
    EXPECT_GT(sc.generation(), gen);
    EXPECT_EQ(sc.extent().width, 96u);
    EXPECT_EQ(sc.extent().height, 80u);
    for (int i = 0; i < 4; ++i) {
      glfwPollEvents();
      render_frame(ctx, frames, sc, float(i) / 4, {uint32_t(w), uint32_t(h)});
    }
    frames.wait_all();
    EXPECT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
  }
  EXPECT_EQ(total_validation_errors(), before);
  glfwDestroyWindow(win);
  glfwTerminate();
}
