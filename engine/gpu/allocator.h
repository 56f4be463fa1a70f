#pragma once
// Device-memory suballocation: one VkDeviceMemory block (64 MiB by default) serves many resources.
//
//   VkMemoryRequirements req; vkGetImageMemoryRequirements(dev, image, &req);
//   gpu::Allocation a = ctx.allocator().allocate(req, gpu::MemoryUsage::GpuOnly, "gbuffer");
//   vkBindImageMemory(dev, image, a.memory, a.offset);
//   ...
//   ctx.allocator().free(a);                     // a is reset; the range returns to its block
//   ctx.allocator().stats().peak_allocated_bytes // "peak GPU memory allocated" for the stats JSON
//
// Aliasing (render graph transients): allocate one range with the max size/alignment and the AND of
// the memoryTypeBits of all images that share it, then bind each image to (a.memory, a.offset).
//
// Rules kept by the allocator:
// - bufferImageGranularity: every suballocation's offset and size are rounded up to it, so linear
//   and optimal resources never share a granularity "page" (simple and safe; lavapipe: 64 bytes).
// - requests over half a block get their own dedicated block.
// - host-visible blocks are mapped once, persistently; Allocation::mapped points at the range.
//   Host-visible types are always chosen HOST_COHERENT, so no flush/invalidate is needed.
// - empty blocks are released, except the last one per memory type (avoids thrash).
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

enum class MemoryUsage {
  GpuOnly,   // DEVICE_LOCAL: images, render targets, storage buffers
  Upload,    // HOST_VISIBLE|COHERENT: staging buffers, written by the CPU once
  Readback,  // HOST_VISIBLE|COHERENT, HOST_CACHED preferred: GPU->CPU copies
  Dynamic,   // HOST_VISIBLE|COHERENT, DEVICE_LOCAL preferred: per-frame uniforms
};

struct Allocation {
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;   // the rounded size actually reserved
  void* mapped = nullptr;  // host pointer to `offset` when host-visible, else null
  uint32_t memory_type = 0;
  uint32_t block = UINT32_MAX;  // allocator-internal
  explicit operator bool() const { return memory != VK_NULL_HANDLE; }
};

struct MemoryStats {
  uint64_t allocated_bytes = 0;       // sum of live suballocations
  uint64_t peak_allocated_bytes = 0;  // max of allocated_bytes over the allocator's life
  uint64_t reserved_bytes = 0;        // sum of live VkDeviceMemory blocks
  uint64_t peak_reserved_bytes = 0;
  uint32_t allocation_count = 0;
  uint32_t block_count = 0;
};

namespace detail {

// Free-list allocator over [0, capacity): best fit (size-indexed), alignment-aware, merges neighbours on free.
// Pure logic, unit-tested without a device.
class RangeAllocator {
 public:
  explicit RangeAllocator(uint64_t capacity);
  // Returns the offset (a multiple of `alignment`, which must be a power of two) or nullopt.
  std::optional<uint64_t> allocate(uint64_t size, uint64_t alignment);
  // Frees exactly a range returned by allocate(). Throws cumulo::Error on overlap (double free).
  void free(uint64_t offset, uint64_t size);
  uint64_t capacity() const { return capacity_; }
  uint64_t used() const { return used_; }
  bool empty() const { return used_ == 0; }
  uint64_t largest_free() const;
  size_t free_range_count() const { return free_.size(); }
  // Internal invariants (for tests): free ranges disjoint and merged, the size index mirrors them,
  // used + free == capacity.
  bool consistent() const;

 private:
  void add_free(uint64_t offset, uint64_t size);
  void remove_free(std::map<uint64_t, uint64_t>::iterator it);

  uint64_t capacity_;
  uint64_t used_ = 0;
  std::map<uint64_t, uint64_t> free_;          // offset -> size, non-adjacent (merged)
  std::multimap<uint64_t, uint64_t> by_size_;  // size -> offset: best fit in O(log n)
};

inline uint64_t align_up(uint64_t v, uint64_t a) { return (v + a - 1) & ~(a - 1); }

// Memory type choice for a usage, from the device's memory properties (pure: unit-tested with
// discrete-GPU-like tables). Returns -1 when no type among `type_bits` qualifies.
int choose_memory_type(const VkPhysicalDeviceMemoryProperties& props, uint32_t type_bits, MemoryUsage usage);

}  // namespace detail

class MemoryAllocator {
 public:
  static constexpr VkDeviceSize kDefaultBlockSize = 64ull << 20;

  MemoryAllocator(VkPhysicalDevice physical, VkDevice device, VkDeviceSize block_size = kDefaultBlockSize);
  ~MemoryAllocator();
  MemoryAllocator(const MemoryAllocator&) = delete;
  MemoryAllocator& operator=(const MemoryAllocator&) = delete;

  // Throws cumulo::Error when no memory type fits or the device is out of memory.
  Allocation allocate(const VkMemoryRequirements& req, MemoryUsage usage, const char* debug_name = nullptr);
  void free(Allocation& allocation);  // resets `allocation`; freeing an empty one is a no-op
  MemoryStats stats() const;
  // Best memory type index for `usage` among `type_bits`; throws when none qualifies.
  uint32_t find_memory_type(uint32_t type_bits, MemoryUsage usage) const;
  bool is_host_visible(uint32_t memory_type) const;
  // Makes every page of each block resident now and of each new block when it is reserved (a device
  // whose memory is host memory, like lavapipe, commits a block's pages only when first written, so
  // a process's resident memory climbs for a while toward the blocks' high-water marks with nothing
  // leaking: `cumulo soak` turns this on there so its resident figure measures host memory alone;
  // device memory is measured by stats()). Contents are kept. Returns false where the kernel cannot.
  bool commit_blocks();

 private:
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    uint32_t memory_type = 0;
    void* mapped = nullptr;
    bool dedicated = false;
    std::unique_ptr<detail::RangeAllocator> ranges;
  };
  bool commit_blocks_ = false;
  uint32_t new_block(uint32_t memory_type, VkDeviceSize size, bool dedicated, const char* debug_name);
  void release_block(uint32_t index);

  VkDevice device_;
  VkPhysicalDeviceMemoryProperties props_{};
  VkDeviceSize block_size_;
  VkDeviceSize granularity_;
  mutable std::mutex mutex_;
  std::vector<Block> blocks_;  // index = Allocation::block; released slots have memory == null
  MemoryStats stats_;
};

}  // namespace cumulo::gpu
