#pragma once
// Minimal SPIR-V reflection: descriptor bindings, push-constant block size, compute local size.
// Enough to derive pipeline layouts from shaders so callers never write layouts by hand.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace cumulo::gpu::detail {

struct ReflectedBinding {
  uint32_t set = 0, binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;
  std::string name;
};

struct ShaderReflection {
  std::vector<ReflectedBinding> bindings;
  uint32_t push_constant_size = 0;
  uint32_t local_size[3] = {1, 1, 1};
};

// Throws cumulo::Error (prefixed with `name`) on malformed SPIR-V or unsupported declarations.
ShaderReflection reflect_spirv(const std::vector<uint32_t>& spirv, const std::string& name);

}  // namespace cumulo::gpu::detail
