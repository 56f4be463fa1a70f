#pragma once
// Descriptor writes for the cloud passes' compute pipelines (push descriptors, set 0) that skip bindings
// the pipeline does not have: reflection drops unused ones and the variants of one shader use different
// subsets, so every variant can be fed by the same code.
//
//   PassBindings(*pipe).ubo(CLOUD_BINDING_PARAMS, buffer, size).sampled(1, view, sampler).push(ctx, cmd);
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"

namespace cumulo::clouds::render {

class PassBindings {
 public:
  explicit PassBindings(const gpu::Pipeline& p) : p_(p) {}
  PassBindings& ubo(uint32_t b, VkBuffer buffer, VkDeviceSize size) {
    if (p_.find_binding(0, b)) w_.uniform_buffer(b, buffer, 0, size);
    return *this;
  }
  PassBindings& sampled(uint32_t b, VkImageView view, VkSampler sampler,
                        VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) {
    if (const gpu::PipelineBinding* pb = p_.find_binding(0, b))
      for (uint32_t e = 0; e < pb->count; ++e) w_.sampled_image(b, view, sampler, layout, e);
    return *this;
  }
  PassBindings& storage(uint32_t b, VkImageView view) {
    if (p_.find_binding(0, b)) w_.storage_image(b, view);
    return *this;
  }
  void push(const gpu::Context& ctx, VkCommandBuffer cmd) const {
    p_.bind(cmd);
    w_.push(ctx, cmd, p_);
  }

 private:
  const gpu::Pipeline& p_;
  gpu::DescriptorWriter w_;
};

}  // namespace cumulo::clouds::render
