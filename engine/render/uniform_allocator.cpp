#include "engine/render/uniform_allocator.h"

#include <string>

#include "engine/core/error.h"
#include "engine/gpu/context.h"

namespace cumulo::render {

UniformAllocator::UniformAllocator(gpu::Context& ctx, uint32_t slots, VkDeviceSize bytes_per_slot)
    : capacity_(bytes_per_slot) {
  alignment_ = std::max<VkDeviceSize>(16, ctx.info().limits.minUniformBufferOffsetAlignment);
  for (uint32_t i = 0; i < slots; ++i) {
    std::string name = "frame uniforms " + std::to_string(i);
    buffers_.emplace_back(ctx, gpu::BufferDesc{bytes_per_slot, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                                               name.c_str()});
  }
}

void UniformAllocator::begin_frame(uint32_t slot) {
  slot_ = slot % uint32_t(buffers_.size());
  head_ = 0;
}

UniformSlice UniformAllocator::allocate(VkDeviceSize bytes) {
  VkDeviceSize offset = (head_ + alignment_ - 1) / alignment_ * alignment_;
  if (bytes == 0 || offset + bytes > capacity_)
    fail("frame uniforms: %llu bytes asked with %llu of %llu used this frame",
         static_cast<unsigned long long>(bytes), static_cast<unsigned long long>(offset),
         static_cast<unsigned long long>(capacity_));
  head_ = offset + bytes;
  const gpu::Buffer& b = buffers_[slot_];
  return {b.handle(), offset, bytes, static_cast<uint8_t*>(b.mapped()) + offset};
}

}  // namespace cumulo::render
