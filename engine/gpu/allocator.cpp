#include "engine/gpu/allocator.h"

#include "engine/gpu/gpu_budget.h"
#include "engine/gpu/live_objects.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>

#include "engine/core/error.h"
#include "engine/core/log.h"

namespace cumulo::gpu {
namespace {

// Makes the pages under [p, p + n) resident without changing their contents (Linux 5.14+).
bool populate_pages(void* p, uint64_t n) {
#ifdef MADV_POPULATE_WRITE
  const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
  const uintptr_t begin = uintptr_t(p) & ~(page - 1);
  const uintptr_t end = (uintptr_t(p) + n + page - 1) & ~(page - 1);
  return madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE) == 0;
#else
  (void)p, (void)n;
  return false;
#endif
}

}  // namespace
namespace detail {

RangeAllocator::RangeAllocator(uint64_t capacity) : capacity_(capacity) {
  if (capacity > 0) add_free(0, capacity);
}

void RangeAllocator::add_free(uint64_t offset, uint64_t size) {
  free_[offset] = size;
  by_size_.emplace(size, offset);
}

void RangeAllocator::remove_free(std::map<uint64_t, uint64_t>::iterator it) {
  auto [lo, hi] = by_size_.equal_range(it->second);
  for (auto s = lo; s != hi; ++s)
    if (s->second == it->first) {
      by_size_.erase(s);
      break;
    }
  free_.erase(it);
}

std::optional<uint64_t> RangeAllocator::allocate(uint64_t size, uint64_t alignment) {
  if (size == 0) size = 1;
  if (alignment == 0) alignment = 1;
  // Best fit: the smallest free range that holds the aligned request keeps big ranges whole.
  // Ranges are visited by increasing size; alignment padding may make a small one too short.
  for (auto s = by_size_.lower_bound(size); s != by_size_.end(); ++s) {
    uint64_t range_off = s->second, range_size = s->first;
    uint64_t start = align_up(range_off, alignment);
    if (start + size > range_off + range_size) continue;
    remove_free(free_.find(range_off));
    if (start > range_off) add_free(range_off, start - range_off);  // alignment gap stays free
    uint64_t end = start + size, range_end = range_off + range_size;
    if (range_end > end) add_free(end, range_end - end);
    used_ += size;
    return start;
  }
  return std::nullopt;
}

void RangeAllocator::free(uint64_t offset, uint64_t size) {
  if (size == 0) size = 1;
  if (offset + size > capacity_)
    fail("RangeAllocator::free: range [%llu, %llu) outside capacity %llu", (unsigned long long)offset,
         (unsigned long long)(offset + size), (unsigned long long)capacity_);
  auto next = free_.lower_bound(offset);
  bool overlap = next != free_.end() && next->first < offset + size;
  if (next != free_.begin()) {
    auto prev = std::prev(next);
    overlap = overlap || prev->first + prev->second > offset;
  }
  if (overlap)
    fail("RangeAllocator::free: range [%llu, %llu) overlaps a free range (double free?)", (unsigned long long)offset,
         (unsigned long long)(offset + size));
  uint64_t start = offset, len = size;
  if (next != free_.end() && next->first == offset + size) {  // merge with the following range
    len += next->second;
    auto after = std::next(next);
    remove_free(next);
    next = after;
  }
  if (next != free_.begin()) {
    auto prev = std::prev(next);
    if (prev->first + prev->second == offset) {  // merge with the preceding range
      start = prev->first;
      len += prev->second;
      remove_free(prev);
    }
  }
  add_free(start, len);
  used_ -= size;
}

bool RangeAllocator::consistent() const {
  if (free_.size() != by_size_.size()) return false;
  uint64_t total = 0, prev_end = 0;
  bool first = true;
  for (auto& [o, sz] : free_) {
    if (sz == 0 || o + sz > capacity_) return false;
    if (!first && o <= prev_end) return false;  // overlapping or adjacent (unmerged)
    first = false;
    prev_end = o + sz;
    total += sz;
    auto [lo, hi] = by_size_.equal_range(sz);
    if (std::none_of(lo, hi, [&](auto& e) { return e.second == o; })) return false;
  }
  return total + used_ == capacity_;
}

uint64_t RangeAllocator::largest_free() const { return by_size_.empty() ? 0 : by_size_.rbegin()->first; }

}  // namespace detail

static const char* usage_name(MemoryUsage u) {
  switch (u) {
    case MemoryUsage::GpuOnly:
      return "GpuOnly";
    case MemoryUsage::Upload:
      return "Upload";
    case MemoryUsage::Readback:
      return "Readback";
    case MemoryUsage::Dynamic:
      return "Dynamic";
  }
  return "?";
}

MemoryAllocator::MemoryAllocator(VkPhysicalDevice physical, VkDevice device, VkDeviceSize block_size)
    : device_(device), block_size_(block_size) {
  vkGetPhysicalDeviceMemoryProperties(physical, &props_);
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(physical, &p);
  granularity_ = std::max<VkDeviceSize>(1, p.limits.bufferImageGranularity);
}

MemoryAllocator::~MemoryAllocator() {
  if (stats_.allocation_count > 0)
    LOG_WARN("gpu: %u allocations (%llu bytes) still live when the allocator was destroyed", stats_.allocation_count,
             (unsigned long long)stats_.allocated_bytes);
  for (auto& b : blocks_)
    if (b.memory) vkFreeMemory(device_, b.memory, nullptr);
}

bool MemoryAllocator::is_host_visible(uint32_t t) const {
  return (props_.memoryTypes[t].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
}

int detail::choose_memory_type(const VkPhysicalDeviceMemoryProperties& props, uint32_t type_bits, MemoryUsage usage) {
  VkMemoryPropertyFlags required = 0, preferred = 0, avoided = 0;
  switch (usage) {
    case MemoryUsage::GpuOnly:
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      avoided = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
      break;
    case MemoryUsage::Upload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      avoided = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;  // keep scarce BAR memory for Dynamic
      break;
    case MemoryUsage::Readback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
    case MemoryUsage::Dynamic:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
  }
  int best = -1, best_score = -1;
  for (uint32_t i = 0; i < props.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    VkMemoryPropertyFlags f = props.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if (f & VK_MEMORY_PROPERTY_LAZILY_ALLOCATED_BIT) continue;
    if (f & VK_MEMORY_PROPERTY_PROTECTED_BIT) continue;
    int score = 4 * __builtin_popcount(f & preferred) + 2 * (((f & avoided) == 0) ? 1 : 0);
    if (score > best_score) {
      best = int(i);
      best_score = score;
    }
  }
  return best;
}

uint32_t MemoryAllocator::find_memory_type(uint32_t type_bits, MemoryUsage usage) const {
  int best = detail::choose_memory_type(props_, type_bits, usage);
  if (best < 0) fail("gpu: no memory type for usage %s among type bits 0x%x", usage_name(usage), type_bits);
  return uint32_t(best);
}

uint32_t MemoryAllocator::new_block(uint32_t memory_type, VkDeviceSize size, bool dedicated, const char* debug_name) {
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = size;
  info.memoryTypeIndex = memory_type;
  VkDeviceMemory mem = VK_NULL_HANDLE;
  VkResult r = vkAllocateMemory(device_, &info, nullptr, &mem);
  if (r != VK_SUCCESS)
    fail("gpu: vkAllocateMemory of %llu bytes (memory type %u%s%s) failed: %s", (unsigned long long)size, memory_type,
         debug_name ? ", for " : "", debug_name ? debug_name : "", vk_result_name(r));
  Block b;
  b.memory = mem;
  b.memory_type = memory_type;
  b.dedicated = dedicated;
  b.ranges = std::make_unique<detail::RangeAllocator>(size);
  if (is_host_visible(memory_type)) VK_CHECK(vkMapMemory(device_, mem, 0, VK_WHOLE_SIZE, 0, &b.mapped));
  if (commit_blocks_ && b.mapped) populate_pages(b.mapped, size);
  stats_.reserved_bytes += size;
  stats_.peak_reserved_bytes = std::max(stats_.peak_reserved_bytes, stats_.reserved_bytes);
  stats_.block_count++;
  for (uint32_t i = 0; i < blocks_.size(); ++i) {
    if (!blocks_[i].memory) {
      blocks_[i] = std::move(b);
      return i;
    }
  }
  blocks_.push_back(std::move(b));
  return uint32_t(blocks_.size() - 1);
}

void MemoryAllocator::release_block(uint32_t index) {
  Block& b = blocks_[index];
  if (b.mapped) vkUnmapMemory(device_, b.memory);
  vkFreeMemory(device_, b.memory, nullptr);
  stats_.reserved_bytes -= b.ranges->capacity();
  stats_.block_count--;
  b = Block{};
}

Allocation MemoryAllocator::allocate(const VkMemoryRequirements& req, MemoryUsage usage, const char* debug_name) {
  uint32_t type = find_memory_type(req.memoryTypeBits, usage);
  VkDeviceSize alignment = std::max<VkDeviceSize>(req.alignment, granularity_);
  VkDeviceSize size = detail::align_up(std::max<VkDeviceSize>(req.size, 1), granularity_);
  std::lock_guard lock(mutex_);
  // Read at each allocation (they are few, and a test may set it per process or per case).
  const uint64_t budget = gpu_memory_budget_bytes();
  if (budget && stats_.allocated_bytes + size > budget) {
    const double mib = double(1 << 20);
    throw GpuBudgetError(strf("%s needs %.1f MiB of GPU memory, but %.1f of the %.1f MiB budget are in use "
                              "(CUMULO_GPU_MEMORY_BUDGET_MB)",
                              debug_name && *debug_name ? debug_name : "an unnamed resource", double(size) / mib,
                              double(stats_.allocated_bytes) / mib, double(budget) / mib));
  }
  uint32_t block = UINT32_MAX;
  std::optional<uint64_t> offset;
  if (size > block_size_ / 2) {
    block = new_block(type, size, true, debug_name);
    offset = blocks_[block].ranges->allocate(size, 1);
  } else {
    for (uint32_t i = 0; i < blocks_.size() && !offset; ++i) {
      Block& b = blocks_[i];
      if (!b.memory || b.dedicated || b.memory_type != type) continue;
      offset = b.ranges->allocate(size, alignment);
      if (offset) block = i;
    }
    if (!offset) {
      block = new_block(type, block_size_, false, debug_name);
      offset = blocks_[block].ranges->allocate(size, alignment);
    }
  }
  Block& b = blocks_[block];
  Allocation a;
  a.memory = b.memory;
  a.offset = *offset;
  a.size = size;
  a.memory_type = type;
  a.block = block;
  a.mapped = b.mapped ? static_cast<char*>(b.mapped) + *offset : nullptr;
  stats_.allocated_bytes += size;
  stats_.peak_allocated_bytes = std::max(stats_.peak_allocated_bytes, stats_.allocated_bytes);
  stats_.allocation_count++;
  detail::note_allocation(a.memory, a.offset, a.size, debug_name);
  return a;
}

void MemoryAllocator::free(Allocation& a) {
  if (!a) return;
  std::lock_guard lock(mutex_);
  if (a.block >= blocks_.size() || blocks_[a.block].memory != a.memory)
    fail("gpu: freeing an allocation this allocator does not own");
  Block& b = blocks_[a.block];
  b.ranges->free(a.offset, a.size);
  detail::note_free(a.memory, a.offset);
  stats_.allocated_bytes -= a.size;
  stats_.allocation_count--;
  if (b.ranges->empty()) {
    bool keep = false;
    if (!b.dedicated) {  // keep the last empty block of this type to avoid allocate/free thrash
      keep = true;
      for (uint32_t i = 0; i < blocks_.size(); ++i)
        if (i != a.block && blocks_[i].memory && !blocks_[i].dedicated && blocks_[i].memory_type == b.memory_type &&
            blocks_[i].ranges->empty())
          keep = false;
    }
    if (!keep) release_block(a.block);
  }
  a = Allocation{};
}

bool MemoryAllocator::commit_blocks() {
  std::lock_guard lock(mutex_);
  commit_blocks_ = true;
  bool ok = true;
  for (const Block& b : blocks_)
    if (b.memory && b.mapped) ok = populate_pages(b.mapped, b.ranges->capacity()) && ok;
  return ok;
}

MemoryStats MemoryAllocator::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

}  // namespace cumulo::gpu
