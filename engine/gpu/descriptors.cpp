#include "engine/gpu/descriptors.h"

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/live_objects.h"
#include "engine/gpu/pipeline.h"

namespace cumulo::gpu {

DescriptorWriter& DescriptorWriter::add(uint32_t binding, VkDescriptorType type, uint32_t element,
                                        const VkDescriptorImageInfo* image, const VkDescriptorBufferInfo* buffer) {
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstBinding = binding;
  w.dstArrayElement = element;
  w.descriptorCount = 1;
  w.descriptorType = type;
  if (image) {
    images_.push_back(*image);
    w.pImageInfo = &images_.back();
  }
  if (buffer) {
    buffers_.push_back(*buffer);
    w.pBufferInfo = &buffers_.back();
  }
  writes_.push_back(w);
  return *this;
}

DescriptorWriter& DescriptorWriter::storage_image(uint32_t b, VkImageView v, VkImageLayout l, uint32_t e) {
  VkDescriptorImageInfo i{VK_NULL_HANDLE, v, l};
  return add(b, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, e, &i, nullptr);
}
DescriptorWriter& DescriptorWriter::sampled_image(uint32_t b, VkImageView v, VkSampler s, VkImageLayout l, uint32_t e) {
  VkDescriptorImageInfo i{s, v, l};
  return add(b, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, e, &i, nullptr);
}
DescriptorWriter& DescriptorWriter::texture(uint32_t b, VkImageView v, VkImageLayout l, uint32_t e) {
  VkDescriptorImageInfo i{VK_NULL_HANDLE, v, l};
  return add(b, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, e, &i, nullptr);
}
DescriptorWriter& DescriptorWriter::sampler(uint32_t b, VkSampler s, uint32_t e) {
  VkDescriptorImageInfo i{s, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_UNDEFINED};
  return add(b, VK_DESCRIPTOR_TYPE_SAMPLER, e, &i, nullptr);
}
DescriptorWriter& DescriptorWriter::uniform_buffer(uint32_t b, VkBuffer buf, VkDeviceSize o, VkDeviceSize r) {
  VkDescriptorBufferInfo i{buf, o, r};
  return add(b, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 0, nullptr, &i);
}
DescriptorWriter& DescriptorWriter::storage_buffer(uint32_t b, VkBuffer buf, VkDeviceSize o, VkDeviceSize r) {
  VkDescriptorBufferInfo i{buf, o, r};
  return add(b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0, nullptr, &i);
}

void DescriptorWriter::push(const Context& ctx, VkCommandBuffer cmd, const Pipeline& p, uint32_t set) const {
  if (set != 0 || !p.set0_is_push())
    fail("pipeline '%s': set %u is not a push-descriptor set (only set 0 is, on devices with VK_KHR_push_descriptor)",
         p.name().c_str(), set);
  for (auto& w : writes_) {
    const PipelineBinding* b = p.find_binding(set, w.dstBinding);
    if (!b) fail("pipeline '%s' has no binding %u in set %u", p.name().c_str(), w.dstBinding, set);
    if (b->type != w.descriptorType)
      fail("pipeline '%s': binding %u ('%s') has descriptor type %d, the write has %d", p.name().c_str(), w.dstBinding,
           b->name.c_str(), int(b->type), int(w.descriptorType));
  }
  ctx.cmd_push_descriptor_set(cmd, p.bind_point(), p.layout(), set, uint32_t(writes_.size()), writes_.data());
}

void DescriptorWriter::update(const Context& ctx, VkDescriptorSet set) const {
  std::vector<VkWriteDescriptorSet> w = writes_;
  for (auto& x : w) x.dstSet = set;
  vkUpdateDescriptorSets(ctx.device(), uint32_t(w.size()), w.data(), 0, nullptr);
}

DescriptorPool::DescriptorPool(Context& ctx, uint32_t max_sets, uint32_t per_type) : ctx_(ctx) {
  if (per_type == 0) per_type = 4 * max_sets;
  VkDescriptorPoolSize sizes[] = {
      {VK_DESCRIPTOR_TYPE_SAMPLER, per_type},        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, per_type},
      {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, per_type},  {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, per_type},
      {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, per_type}, {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, per_type},
  };
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = max_sets;
  info.poolSizeCount = uint32_t(std::size(sizes));
  info.pPoolSizes = sizes;
  VK_CHECK(vkCreateDescriptorPool(ctx.device(), &info, nullptr, &pool_));
  detail::count_live(detail::LiveKind::DescriptorPool, 1);
}

DescriptorPool::~DescriptorPool() {
  vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
  detail::count_live(detail::LiveKind::DescriptorPool, -1);
  detail::count_live(detail::LiveKind::DescriptorSet, -int64_t(sets_));
}

VkDescriptorSet DescriptorPool::allocate(VkDescriptorSetLayout layout) {
  VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  info.descriptorPool = pool_;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &layout;
  VkDescriptorSet set;
  VkResult r = vkAllocateDescriptorSets(ctx_.device(), &info, &set);
  if (r != VK_SUCCESS)
    fail("gpu: descriptor pool exhausted (%s); reset it per frame or make it larger", vk_result_name(r));
  ++sets_;
  detail::count_live(detail::LiveKind::DescriptorSet, 1);
  return set;
}

void DescriptorPool::reset() {
  vkResetDescriptorPool(ctx_.device(), pool_, 0);
  detail::count_live(detail::LiveKind::DescriptorSet, -int64_t(sets_));
  sets_ = 0;
}

}  // namespace cumulo::gpu
