#include "engine/gpu/detail/device_select.h"

#include <algorithm>
#include <cctype>

#include "engine/core/error.h"

namespace cumulo::gpu::detail {

int device_type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 1;
    default:
      return 0;
  }
}

static std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

static std::string list_devices(const std::vector<DeviceCandidate>& c) {
  std::string out;
  for (size_t i = 0; i < c.size(); ++i) {
    out += strf("\n  [%zu] %s%s%s", i, c[i].name.c_str(),
                c[i].suitable ? "" : " (unsuitable: ", c[i].suitable ? "" : (c[i].why_not + ")").c_str());
  }
  return out.empty() ? std::string("\n  (no Vulkan devices)") : out;
}

int choose_device(const std::vector<DeviceCandidate>& candidates, const std::string& override_spec) {
  if (!override_spec.empty()) {
    bool numeric =
        std::all_of(override_spec.begin(), override_spec.end(), [](unsigned char ch) { return std::isdigit(ch); });
    int found = -1;
    if (numeric) {
      size_t idx = std::stoul(override_spec);
      if (idx < candidates.size()) found = int(idx);
    } else {
      std::string want = lower(override_spec);
      for (size_t i = 0; i < candidates.size(); ++i) {
        if (lower(candidates[i].name).find(want) != std::string::npos) {
          found = int(i);
          if (candidates[i].suitable) break;  // prefer a suitable match when several names match
        }
      }
    }
    if (found < 0)
      fail("CUMULO_DEVICE='%s' matches no Vulkan device; devices:%s", override_spec.c_str(),
           list_devices(candidates).c_str());
    if (!candidates[found].suitable)
      fail("CUMULO_DEVICE='%s' selects '%s', which is unsuitable: %s", override_spec.c_str(),
           candidates[found].name.c_str(), candidates[found].why_not.c_str());
    return found;
  }
  int best = -1;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!candidates[i].suitable) continue;
    if (best < 0 || device_type_rank(candidates[i].type) > device_type_rank(candidates[best].type)) best = int(i);
  }
  if (best < 0)
    fail(
        "no suitable Vulkan device (need Vulkan 1.3 with synchronization2, dynamic rendering, timeline semaphores); "
        "devices:%s",
        list_devices(candidates).c_str());
  return best;
}

}  // namespace cumulo::gpu::detail
