#pragma once
// Swapchain on the Context's surface (created by the platform layer and handed over through
// ContextDesc::create_surface), recreated on resize, VK_ERROR_OUT_OF_DATE_KHR and VK_SUBOPTIMAL_KHR.
//
//   gpu::Swapchain swapchain(ctx, {window->width(), window->height()});
//   // per frame:
//   if (window->consume_resized()) swapchain.recreate({window->width(), window->height()});
//   gpu::Frame& f = frames.begin();
//   std::optional<uint32_t> i = swapchain.acquire(f.acquired);
//   if (!i) { frames.submit(f); swapchain.recreate(size); continue; }  // out of date: skip this frame
//   // transition swapchain.image(*i) from swapchain.layout(*i) (UNDEFINED or PRESENT_SRC) ... to PRESENT_SRC,
//   // then swapchain.set_layout(*i, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR)
//   frames.submit(f, f.acquired, swapchain.render_finished(*i));
//   if (!swapchain.present(*i)) swapchain.recreate(size);
//
// Images carry COLOR_ATTACHMENT usage, plus TRANSFER_DST/SRC and STORAGE when the surface allows
// (check usage()). vsync = FIFO; otherwise MAILBOX, then IMMEDIATE when available.
#include <optional>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

struct SwapchainDesc {
  bool vsync = true;
  bool srgb = false;  // true: an *_SRGB format (hardware encodes); false: UNORM (the tonemap pass encodes)
};

class Swapchain {
 public:
  Swapchain(Context& ctx, VkExtent2D framebuffer_size, const SwapchainDesc& desc = {});
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Returns the acquired image index, or nullopt when the swapchain is out of date (then `acquired`
  // is NOT signalled: don't wait on it). A suboptimal acquire returns the index and sets needs_recreate().
  std::optional<uint32_t> acquire(VkSemaphore acquired, uint64_t timeout_ns = UINT64_MAX);
  // Queues `index` for presentation after render_finished(index). False when it should be recreated.
  bool present(uint32_t index);
  // Waits for the device, rebuilds for the new size. A 0x0 size (minimized) is ignored: returns false.
  bool recreate(VkExtent2D framebuffer_size);
  bool needs_recreate() const { return needs_recreate_; }

  VkSwapchainKHR handle() const { return swapchain_; }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  VkImageUsageFlags usage() const { return usage_; }
  VkPresentModeKHR present_mode() const { return present_mode_; }
  uint32_t image_count() const { return uint32_t(images_.size()); }
  VkImage image(uint32_t i) const { return images_[i]; }
  VkImageView view(uint32_t i) const { return views_[i]; }
  VkSemaphore render_finished(uint32_t i) const { return render_finished_[i]; }
  VkImageLayout layout(uint32_t i) const { return layouts_[i]; }
  void set_layout(uint32_t i, VkImageLayout l) { layouts_[i] = l; }
  uint32_t generation() const { return generation_; }  // bumps on each recreate

 private:
  void create(VkExtent2D size);
  void destroy_views();

  Context& ctx_;
  SwapchainDesc desc_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkColorSpaceKHR color_space_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  VkExtent2D extent_{};
  VkImageUsageFlags usage_ = 0;
  VkPresentModeKHR present_mode_ = VK_PRESENT_MODE_FIFO_KHR;
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
  std::vector<VkSemaphore> render_finished_;  // per image: a present may still wait on it when a slot is reused
  std::vector<VkImageLayout> layouts_;
  bool needs_recreate_ = false;
  uint32_t generation_ = 0;
};

}  // namespace cumulo::gpu
