#pragma once
// Device choice, separated from Vulkan calls so it can be unit-tested without a device.
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

namespace cumulo::gpu::detail {

struct DeviceCandidate {
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  bool suitable = true;  // has Vulkan 1.3, the features we need, a usable queue family
  std::string why_not;   // when !suitable
};

// Rank: discrete > integrated > virtual > CPU > other.
int device_type_rank(VkPhysicalDeviceType type);

// Returns the index of the chosen candidate. `override_spec` (from CUMULO_DEVICE) is either an index
// or a case-insensitive substring of the device name; it must match a suitable device or this
// throws cumulo::Error listing the devices. Without an override, the best-ranked suitable device
// wins (first in enumeration order on ties). Throws when no device is suitable.
int choose_device(const std::vector<DeviceCandidate>& candidates, const std::string& override_spec);

}  // namespace cumulo::gpu::detail
