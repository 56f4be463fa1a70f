#pragma once
// RAII buffer with suballocated memory.
//
//   gpu::Buffer ssbo(ctx, {.size = 1024, .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .name = "particles"});
//   ssbo.upload(data.data(), data.size() * sizeof(float));     // staging + submit_and_wait if not host-visible
//   gpu::Buffer ubo(ctx, {.size = sizeof(Params), .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
//                         .memory = gpu::MemoryUsage::Dynamic});
//   std::memcpy(ubo.mapped(), &params, sizeof params);        // persistently mapped, coherent
//   ssbo.download(out.data(), bytes);                          // GPU -> CPU (waits)
#include <cstdint>

#include "engine/gpu/allocator.h"
#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

struct BufferDesc {
  VkDeviceSize size = 0;
  VkBufferUsageFlags usage = 0;  // TRANSFER_SRC/DST are added so upload()/download() always work
  MemoryUsage memory = MemoryUsage::GpuOnly;
  const char* name = nullptr;  // debug-utils name
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& ctx, const BufferDesc& desc);
  ~Buffer() { reset(); }
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  void reset();  // destroys the buffer and frees its memory (immediately: caller ensures the GPU is done)
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return allocation_.mapped; }  // null unless host-visible
  template <class T>
  T* mapped_as() const {
    return static_cast<T*>(allocation_.mapped);
  }
  const Allocation& allocation() const { return allocation_; }
  VkDescriptorBufferInfo descriptor(VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE) const {
    return {buffer_, offset, range};
  }

  // CPU -> buffer. Host-visible: memcpy (immediately: the GPU must not be using the range; on
  // lavapipe every buffer is host-visible). Otherwise a staging copy on the queue, waited for, followed
  // by a barrier that makes the data visible to every later command.
  void upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  // Buffer -> CPU; waits for the queue copy when not host-visible. Callers make sure earlier GPU
  // writes are complete (e.g. after submit_and_wait).
  void download(void* out, VkDeviceSize bytes, VkDeviceSize offset = 0) const;

 private:
  Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  Allocation allocation_;
};

}  // namespace cumulo::gpu
