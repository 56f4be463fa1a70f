#pragma once
// How the grow_gpu passes are recorded: the solver's parameter block at binding 0 and the pass's buffers at
// bindings 1, 2, ... in the order given (push descriptors), GrowPush as push constants; and the one barrier placed
// between dependent passes (every pass of a step reads what the one before wrote, so a global memory barrier says it
// all; the step runs outside the render graph).
#include <initializer_list>

#include "engine/gpu/vk.h"
#include "shared/grow_params.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
}  // namespace cumulo::gpu

namespace cumulo::clouds::grow_gpu {

class GrowDispatch {
 public:
  GrowDispatch(const gpu::Context& ctx, VkBuffer params) : ctx_(ctx), params_(params) {}
  // ceil(threads / local size) groups.
  void threads(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
               uint32_t threads, const shared::GrowPush& push = {}) const;
  void groups(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers, uint32_t groups,
              const shared::GrowPush& push = {}) const;
  // The group counts from a VkDispatchIndirectCommand in `args` at `offset` (bytes).
  void indirect(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers, VkBuffer args,
                VkDeviceSize offset, const shared::GrowPush& push = {}) const;

 private:
  void bind(VkCommandBuffer cmd, const gpu::Pipeline& pipe, std::initializer_list<VkBuffer> buffers,
            const shared::GrowPush& push) const;
  const gpu::Context& ctx_;
  VkBuffer params_;
};

// Every earlier compute or transfer write visible to every later compute, transfer or indirect-dispatch access.
void grow_barrier(VkCommandBuffer cmd);

}  // namespace cumulo::clouds::grow_gpu
