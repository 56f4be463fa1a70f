#include "engine/gpu/buffer.h"

#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/context.h"
#include "engine/gpu/live_objects.h"

namespace cumulo::gpu {

Buffer::Buffer(Context& ctx, const BufferDesc& desc) : ctx_(&ctx), size_(desc.size) {
  if (desc.size == 0) fail("gpu: buffer '%s' has size 0", desc.name ? desc.name : "");
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = desc.size;
  info.usage = desc.usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(ctx.device(), &info, nullptr, &buffer_));
  detail::count_live(detail::LiveKind::Buffer, 1);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
  try {
    allocation_ = ctx.allocator().allocate(req, desc.memory, desc.name);
  } catch (...) {
    vkDestroyBuffer(ctx.device(), buffer_, nullptr);
    detail::count_live(detail::LiveKind::Buffer, -1);
    buffer_ = VK_NULL_HANDLE;
    throw;
  }
  VK_CHECK(vkBindBufferMemory(ctx.device(), buffer_, allocation_.memory, allocation_.offset));
  if (desc.name) ctx.set_name(buffer_, desc.name);
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    reset();
    ctx_ = o.ctx_;
    buffer_ = o.buffer_;
    size_ = o.size_;
    allocation_ = o.allocation_;
    o.buffer_ = VK_NULL_HANDLE;
    o.allocation_ = Allocation{};
    o.size_ = 0;
  }
  return *this;
}

void Buffer::reset() {
  if (buffer_) {
    vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
    detail::count_live(detail::LiveKind::Buffer, -1);
  }
  if (allocation_) ctx_->allocator().free(allocation_);
  buffer_ = VK_NULL_HANDLE;
  size_ = 0;
}

void Buffer::upload(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (offset + bytes > size_)
    fail("gpu: upload of %llu bytes at %llu overflows a %llu-byte buffer", (unsigned long long)bytes,
         (unsigned long long)offset, (unsigned long long)size_);
  if (bytes == 0) return;
  if (mapped()) {
    std::memcpy(static_cast<char*>(mapped()) + offset, data, bytes);
    return;
  }
  Buffer staging(*ctx_, {.size = bytes,
                         .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         .memory = MemoryUsage::Upload,
                         .name = "upload staging"});
  std::memcpy(staging.mapped(), data, bytes);
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
    // Earlier submissions may still read or write this range (WAR/WAW across submissions).
    cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                       VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.handle(), buffer_, 1, &region);
    cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

void Buffer::download(void* out, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (offset + bytes > size_)
    fail("gpu: download of %llu bytes at %llu overflows a %llu-byte buffer", (unsigned long long)bytes,
         (unsigned long long)offset, (unsigned long long)size_);
  if (bytes == 0) return;
  if (mapped()) {
    // Device writes from earlier submissions must be made visible to the host: a fence wait alone
    // does not do that (on lavapipe every memory type is mapped, so this is the usual path there).
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
      cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    });
    std::memcpy(out, static_cast<const char*>(mapped()) + offset, bytes);
    return;
  }
  Buffer staging(*ctx_, {.size = bytes,
                         .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         .memory = MemoryUsage::Readback,
                         .name = "readback staging"});
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
    // Earlier submissions may have written this buffer (shader or transfer): order them before the copy.
    cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.handle(), 1, &region);
    cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::memcpy(out, staging.mapped(), bytes);
}

}  // namespace cumulo::gpu
