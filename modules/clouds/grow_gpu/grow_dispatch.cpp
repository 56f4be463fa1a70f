#include "modules/clouds/grow_gpu/grow_dispatch.h"

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"

namespace cumulo::clouds::grow_gpu {

void GrowDispatch::bind(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
                        const shared::GrowPush& push) const {
  pipe.bind(cmd);
  gpu::DescriptorWriter writer;
  // A shader may leave the parameter block or a buffer unused (the compiler drops it): write only what it declares.
  if (pipe.find_binding(0, GROW_BINDING_PARAMS)) writer.uniform_buffer(GROW_BINDING_PARAMS, params_);
  uint32_t binding = GROW_BINDING_PARAMS + 1;
  for (VkBuffer b : buffers) {
    if (pipe.find_binding(0, binding)) writer.storage_buffer(binding, b);
    ++binding;
  }
  for (const gpu::PipelineBinding& b : pipe.bindings())
    if (b.set == 0 && b.binding >= binding)
      fail("grow_gpu: pass '%s' declares binding %u, not given", pipe.name().c_str(), b.binding);
  writer.push(ctx_, cmd, pipe);
  if (pipe.push_constant_size() >= sizeof(push)) pipe.push_constants(cmd, push);
}

void GrowDispatch::threads(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
                           uint32_t threads, const shared::GrowPush& push) const {
  bind(cmd, pipe, buffers, push);
  pipe.dispatch_threads(cmd, threads);
}

void GrowDispatch::groups(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
                          uint32_t groups, const shared::GrowPush& push) const {
  bind(cmd, pipe, buffers, push);
  vkCmdDispatch(cmd, groups, 1, 1);
}

void GrowDispatch::indirect(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
                            VkBuffer args, VkDeviceSize offset, const shared::GrowPush& push) const {
  bind(cmd, pipe, buffers, push);
  vkCmdDispatchIndirect(cmd, args, offset);
}

void grow_barrier(VkCommandBuffer cmd) {
  gpu::cmd_memory_barrier(
      cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
      VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT,
      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_UNIFORM_READ_BIT |
          VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

}  // namespace cumulo::clouds::grow_gpu
