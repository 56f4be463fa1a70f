#pragma once
// Descriptor writes (push descriptors for set 0, ordinary sets from a pool for sets 1+).
//
//   gpu::DescriptorWriter()
//       .storage_image(0, out.view())                                  // layout GENERAL
//       .sampled_image(1, noise.view(), ctx.samplers().get(gpu::SamplerDesc::linear_repeat()))
//       .uniform_buffer(2, params.handle())
//       .push(ctx, cmd, pipeline);                                      // set 0, vkCmdPushDescriptorSetKHR
//
//   gpu::DescriptorPool pool(ctx, 64);                                  // reset() once per frame slot
//   VkDescriptorSet set = pool.allocate(pipeline.set_layout(1));
//   gpu::DescriptorWriter().storage_buffer(0, buf.handle()).update(ctx, set);
//   vkCmdBindDescriptorSets(cmd, pipeline.bind_point(), pipeline.layout(), 1, 1, &set, 0, nullptr);
#include <deque>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;
class Pipeline;

class DescriptorWriter {
 public:
  DescriptorWriter& storage_image(uint32_t binding, VkImageView view, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL,
                                  uint32_t array_element = 0);
  DescriptorWriter& sampled_image(uint32_t binding, VkImageView view, VkSampler sampler,  // combined image sampler
                                  VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                  uint32_t array_element = 0);
  DescriptorWriter& texture(uint32_t binding, VkImageView view,  // separate sampled image (texture2D)
                            VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                            uint32_t array_element = 0);
  DescriptorWriter& sampler(uint32_t binding, VkSampler sampler, uint32_t array_element = 0);
  DescriptorWriter& uniform_buffer(uint32_t binding, VkBuffer buffer, VkDeviceSize offset = 0,
                                   VkDeviceSize range = VK_WHOLE_SIZE);
  DescriptorWriter& storage_buffer(uint32_t binding, VkBuffer buffer, VkDeviceSize offset = 0,
                                   VkDeviceSize range = VK_WHOLE_SIZE);

  // Pushes the writes as `set` (which must be the pipeline's push-descriptor set 0).
  void push(const Context& ctx, VkCommandBuffer cmd, const Pipeline& pipeline, uint32_t set = 0) const;
  void update(const Context& ctx, VkDescriptorSet set) const;
  size_t size() const { return writes_.size(); }

 private:
  DescriptorWriter& add(uint32_t binding, VkDescriptorType type, uint32_t element, const VkDescriptorImageInfo* image,
                        const VkDescriptorBufferInfo* buffer);
  std::deque<VkDescriptorImageInfo> images_;  // deque: stable addresses for pImageInfo
  std::deque<VkDescriptorBufferInfo> buffers_;
  std::vector<VkWriteDescriptorSet> writes_;
};

// A pool for ordinary descriptor sets; reset() frees every set allocated from it.
class DescriptorPool {
 public:
  DescriptorPool(Context& ctx, uint32_t max_sets, uint32_t descriptors_per_type = 0 /* 0: 4 * max_sets */);
  ~DescriptorPool();
  DescriptorPool(const DescriptorPool&) = delete;
  DescriptorPool& operator=(const DescriptorPool&) = delete;
  VkDescriptorSet allocate(VkDescriptorSetLayout layout);  // throws when the pool is exhausted
  void reset();
  VkDescriptorPool handle() const { return pool_; }

 private:
  Context& ctx_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  uint64_t sets_ = 0;  // allocated since the last reset (gpu/live_objects.h)
};

}  // namespace cumulo::gpu
