#include "engine/gpu/sampler.h"

#include "engine/gpu/context.h"

namespace cumulo::gpu {

SamplerCache::~SamplerCache() {
  for (auto& [d, s] : entries_) vkDestroySampler(ctx_.device(), s, nullptr);
}

VkSampler SamplerCache::get(const SamplerDesc& d) {
  std::lock_guard lock(mutex_);
  for (auto& [desc, s] : entries_)
    if (desc == d) return s;
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = info.minFilter = d.filter;
  info.mipmapMode = d.mipmap;
  info.addressModeU = info.addressModeV = info.addressModeW = d.address;
  info.maxLod = d.max_lod;
  info.borderColor = d.border;
  if (d.max_anisotropy > 1.0f && ctx_.info().sampler_anisotropy) {
    info.anisotropyEnable = VK_TRUE;
    info.maxAnisotropy = std::min(d.max_anisotropy, ctx_.info().limits.maxSamplerAnisotropy);
  }
  VkSampler s;
  VK_CHECK(vkCreateSampler(ctx_.device(), &info, nullptr, &s));
  ctx_.set_name(s, "cached sampler");
  entries_.emplace_back(d, s);
  return s;
}

}  // namespace cumulo::gpu
