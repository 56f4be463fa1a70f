#include "engine/gpu/swapchain.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

Swapchain::Swapchain(Context& ctx, VkExtent2D size, const SwapchainDesc& desc) : ctx_(ctx), desc_(desc) {
  if (!ctx.surface()) fail("gpu: Swapchain needs a Context created with create_surface");
  if (size.width == 0 || size.height == 0) size = {1, 1};
  create(size);
}

Swapchain::~Swapchain() {
  ctx_.wait_idle();
  destroy_views();
  for (VkSemaphore s : render_finished_) vkDestroySemaphore(ctx_.device(), s, nullptr);
  if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
}

void Swapchain::destroy_views() {
  for (VkImageView v : views_) vkDestroyImageView(ctx_.device(), v, nullptr);
  views_.clear();
}

void Swapchain::create(VkExtent2D size) {
  VkPhysicalDevice pd = ctx_.physical_device();
  VkSurfaceKHR surface = ctx_.surface();
  VkSurfaceCapabilitiesKHR caps;
  VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &caps));
  uint32_t n = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(n);
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data());
  if (formats.empty()) fail("gpu: the surface reports no formats");
  VkFormat wanted[2] = {desc_.srgb ? VK_FORMAT_B8G8R8A8_SRGB : VK_FORMAT_B8G8R8A8_UNORM,
                        desc_.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM};
  VkSurfaceFormatKHR chosen = formats[0];
  for (VkFormat w : wanted) {
    auto it = std::find_if(formats.begin(), formats.end(),
                           [&](auto& f) { return f.format == w && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR; });
    if (it != formats.end()) {
      chosen = *it;
      break;
    }
  }
  format_ = chosen.format;
  color_space_ = chosen.colorSpace;

  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr);
  std::vector<VkPresentModeKHR> modes(n);
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data());
  present_mode_ = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  if (!desc_.vsync) {
    for (VkPresentModeKHR m : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
      if (std::find(modes.begin(), modes.end(), m) != modes.end()) {
        present_mode_ = m;
        break;
      }
  }

  if (caps.currentExtent.width != UINT32_MAX) {
    extent_ = caps.currentExtent;
  } else {
    extent_.width = std::clamp(size.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent_.height = std::clamp(size.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  uint32_t count = std::max(caps.minImageCount + 1, 3u);
  if (caps.maxImageCount) count = std::min(count, caps.maxImageCount);
  usage_ = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  for (VkImageUsageFlags u : {VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_USAGE_TRANSFER_SRC_BIT})
    if (caps.supportedUsageFlags & u) usage_ |= u;

  VkSwapchainKHR old = swapchain_;
  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = count;
  info.imageFormat = format_;
  info.imageColorSpace = color_space_;
  info.imageExtent = extent_;
  info.imageArrayLayers = 1;
  info.imageUsage = usage_;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR)
                          ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                          : caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR))
    info.compositeAlpha = VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
  info.presentMode = present_mode_;
  info.clipped = VK_TRUE;
  info.oldSwapchain = old;
  VK_CHECK(vkCreateSwapchainKHR(ctx_.device(), &info, nullptr, &swapchain_));
  if (old) vkDestroySwapchainKHR(ctx_.device(), old, nullptr);

  vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, nullptr);
  images_.resize(n);
  vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, images_.data());
  destroy_views();
  for (uint32_t i = 0; i < n; ++i) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = images_[i];
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format_;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView v;
    VK_CHECK(vkCreateImageView(ctx_.device(), &vi, nullptr, &v));
    views_.push_back(v);
    ctx_.set_name(images_[i], "swapchain image " + std::to_string(i));
  }
  // Semaphores are recreated too: an out-of-date present may leave one signalled-but-unwaited.
  for (VkSemaphore s : render_finished_) vkDestroySemaphore(ctx_.device(), s, nullptr);
  render_finished_.assign(n, VK_NULL_HANDLE);
  for (auto& s : render_finished_) {
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK_CHECK(vkCreateSemaphore(ctx_.device(), &si, nullptr, &s));
  }
  layouts_.assign(n, VK_IMAGE_LAYOUT_UNDEFINED);
  needs_recreate_ = false;
  ++generation_;
  LOG_DEBUG("gpu: swapchain %ux%u, %u images, format %d, present mode %d", extent_.width, extent_.height, n,
            int(format_), int(present_mode_));
}

bool Swapchain::recreate(VkExtent2D size) {
  if (size.width == 0 || size.height == 0) return false;
  ctx_.wait_idle();
  create(size);
  return true;
}

std::optional<uint32_t> Swapchain::acquire(VkSemaphore acquired, uint64_t timeout_ns) {
  uint32_t index = 0;
  VkResult r = vkAcquireNextImageKHR(ctx_.device(), swapchain_, timeout_ns, acquired, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) {
    needs_recreate_ = true;
    return std::nullopt;
  }
  if (r == VK_SUBOPTIMAL_KHR)
    needs_recreate_ = true;
  else if (r != VK_SUCCESS)
    vk_fail(r, "vkAcquireNextImageKHR", __FILE__, __LINE__);
  return index;
}

bool Swapchain::present(uint32_t index) {
  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.waitSemaphoreCount = 1;
  info.pWaitSemaphores = &render_finished_[index];
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_;
  info.pImageIndices = &index;
  VkResult r;
  {
    std::lock_guard lock(ctx_.queue_mutex());
    r = vkQueuePresentKHR(ctx_.queue(), &info);
  }
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
    needs_recreate_ = true;
    return false;
  }
  if (r != VK_SUCCESS) vk_fail(r, "vkQueuePresentKHR", __FILE__, __LINE__);
  return !needs_recreate_;
}

}  // namespace cumulo::gpu
