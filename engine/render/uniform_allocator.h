#pragma once
// Per-frame uniform memory for passes: one persistently mapped, host-visible buffer per frame slot,
// handed out linearly and rewound when that slot's frame begins again (its previous use completed,
// gpu::FrameRing waited on its fence). A pass copies its parameter block in while the graph is
// built and binds (buffer, offset, size) when it records.
//
//   UniformSlice u = uniforms.push(params);                 // during graph setup
//   DescriptorWriter().uniform_buffer(0, u.buffer, u.offset, u.size)...   // in the pass
#include <cstdint>
#include <cstring>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/gpu/vk.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::render {

struct UniformSlice {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0, size = 0;
  void* mapped = nullptr;
};

class UniformAllocator {
 public:
  UniformAllocator(gpu::Context& ctx, uint32_t slots, VkDeviceSize bytes_per_slot = 256 * 1024);

  // Rewinds `slot`'s buffer: every earlier slice of that slot becomes invalid.
  void begin_frame(uint32_t slot);
  // `bytes` of this frame's memory, aligned for a uniform-buffer binding. Throws cumulo::Error when
  // the slot is full (the message names the capacity, so a module that needs more can say so).
  UniformSlice allocate(VkDeviceSize bytes);
  template <class T>
  UniformSlice push(const T& value) {
    UniformSlice s = allocate(sizeof(T));
    std::memcpy(s.mapped, &value, sizeof(T));
    return s;
  }
  VkDeviceSize used() const { return head_; }
  VkDeviceSize capacity() const { return capacity_; }

 private:
  std::vector<gpu::Buffer> buffers_;
  VkDeviceSize capacity_ = 0, alignment_ = 256, head_ = 0;
  uint32_t slot_ = 0;
};

}  // namespace cumulo::render
