#include "engine/gpu/live_objects.h"

#include <atomic>
#include <mutex>
#include <unordered_map>

namespace cumulo::gpu {
namespace {

std::atomic<int64_t> g_counts[5];

struct Named {
  std::string name;
  uint64_t size = 0;
};
struct MemoryKey {
  uint64_t memory, offset;
  bool operator==(const MemoryKey&) const = default;
};
struct MemoryKeyHash {
  size_t operator()(const MemoryKey& k) const { return std::hash<uint64_t>()(k.memory * 0x9E3779B97F4A7C15ull ^ k.offset); }
};
std::mutex g_mutex;
std::unordered_map<MemoryKey, Named, MemoryKeyHash>& allocations() {
  static std::unordered_map<MemoryKey, Named, MemoryKeyHash> a;
  return a;
}

MemoryKey key(VkDeviceMemory memory, VkDeviceSize offset) { return {uint64_t(uintptr_t(memory)), uint64_t(offset)}; }

}  // namespace

LiveObjects live_objects() {
  using K = detail::LiveKind;
  auto at = [](K k) { return g_counts[int(k)].load(); };
  return {at(K::Image), at(K::Buffer), at(K::Pipeline), at(K::DescriptorPool), at(K::DescriptorSet)};
}

std::map<std::string, uint64_t> live_memory_by_name() {
  std::lock_guard lock(g_mutex);
  std::map<std::string, uint64_t> out;
  for (const auto& [k, n] : allocations()) out[n.name] += n.size;
  return out;
}

namespace detail {

void count_live(LiveKind kind, int64_t delta) { g_counts[int(kind)] += delta; }

void note_allocation(VkDeviceMemory memory, VkDeviceSize offset, VkDeviceSize size, const char* name) {
  std::lock_guard lock(g_mutex);
  allocations()[key(memory, offset)] = Named{name && *name ? name : "(unnamed)", size};
}

void note_free(VkDeviceMemory memory, VkDeviceSize offset) {
  std::lock_guard lock(g_mutex);
  allocations().erase(key(memory, offset));
}

}  // namespace detail
}  // namespace cumulo::gpu
