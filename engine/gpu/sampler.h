#pragma once
// Sampler cache: samplers are deduplicated by description and live as long as the Context.
//
//   VkSampler s = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
//   VkSampler c = ctx.samplers().get({.filter = VK_FILTER_NEAREST, .address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE});
#include <mutex>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

struct SamplerDesc {
  VkFilter filter = VK_FILTER_LINEAR;
  VkSamplerMipmapMode mipmap = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  VkSamplerAddressMode address = VK_SAMPLER_ADDRESS_MODE_REPEAT;  // u, v and w
  float max_lod = VK_LOD_CLAMP_NONE;
  float max_anisotropy = 0.0f;  // > 1 enables anisotropy when the device supports it
  VkBorderColor border = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
  bool operator==(const SamplerDesc&) const = default;

  static SamplerDesc linear_repeat() { return {}; }
  static SamplerDesc linear_clamp() { return {.address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE}; }
  static SamplerDesc nearest_clamp() {
    return {.filter = VK_FILTER_NEAREST,
            .mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST,
            .address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE};
  }
};

class Context;

class SamplerCache {
 public:
  explicit SamplerCache(Context& ctx) : ctx_(ctx) {}
  ~SamplerCache();
  SamplerCache(const SamplerCache&) = delete;
  SamplerCache& operator=(const SamplerCache&) = delete;
  VkSampler get(const SamplerDesc& desc);
  size_t size() const { return entries_.size(); }

 private:
  Context& ctx_;
  std::mutex mutex_;
  std::vector<std::pair<SamplerDesc, VkSampler>> entries_;  // a handful: linear search is fine
};

}  // namespace cumulo::gpu
