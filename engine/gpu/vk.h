#pragma once
// Vulkan include + the one error-check macro used across engine/gpu.
//
//   VK_CHECK(vkCreateFence(dev, &info, nullptr, &fence));   // throws cumulo::Error "vkCreateFence(...): VK_ERROR_..."
//
// Vulkan failures at creation time throw cumulo::Error (a load boundary: the caller reports it);
// per-frame code paths check results explicitly instead (VK_ERROR_OUT_OF_DATE_KHR is not an error).
#include <vulkan/vulkan.h>

namespace cumulo::gpu {

const char* vk_result_name(VkResult r);
[[noreturn]] void vk_fail(VkResult r, const char* expr, const char* file, int line);

}  // namespace cumulo::gpu

#define VK_CHECK(expr)                                                                             \
  do {                                                                                             \
    VkResult vk_check_result_ = (expr);                                                            \
    if (vk_check_result_ < 0) ::cumulo::gpu::vk_fail(vk_check_result_, #expr, __FILE__, __LINE__); \
  } while (0)
