#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "engine/core/error.h"
#include "engine/gpu/allocator.h"

using cumulo::gpu::detail::RangeAllocator;

TEST(RangeAllocator, AllocatesAlignedAndMergesOnFree) {
  RangeAllocator r(1024);
  auto a = r.allocate(100, 1);
  auto b = r.allocate(100, 256);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(*a, 0u);
  EXPECT_EQ(*b % 256, 0u);
  EXPECT_GE(*b, 100u);
  EXPECT_EQ(r.used(), 200u);
  r.free(*a, 100);
  r.free(*b, 100);
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.free_range_count(), 1u);  // everything merged back into one range
  EXPECT_EQ(r.largest_free(), 1024u);
}

TEST(RangeAllocator, FailsWhenFullAndReusesFreedHoles) {
  RangeAllocator r(1000);
  auto a = r.allocate(400, 1), b = r.allocate(400, 1);
  ASSERT_TRUE(a && b);
  EXPECT_FALSE(r.allocate(300, 1));
  r.free(*a, 400);
  auto c = r.allocate(300, 1);
  ASSERT_TRUE(c);
  EXPECT_EQ(*c, *a);
}

TEST(RangeAllocator, BestFitKeepsLargeRangeWhole) {
  RangeAllocator r(1000);
  auto a = r.allocate(100, 1), gap = r.allocate(50, 1), b = r.allocate(100, 1);
  ASSERT_TRUE(a && gap && b);
  r.free(*gap, 50);  // hole of 50 between a and b, plus the 750 tail
  auto c = r.allocate(40, 1);
  ASSERT_TRUE(c);
  EXPECT_EQ(*c, *gap);  // best fit takes the small hole
  EXPECT_EQ(r.largest_free(), 750u);
}

TEST(RangeAllocator, DoubleFreeThrows) {
  RangeAllocator r(256);
  auto a = r.allocate(64, 1);
  ASSERT_TRUE(a);
  r.free(*a, 64);
  EXPECT_THROW(r.free(*a, 64), cumulo::Error);
  EXPECT_THROW(r.free(250, 64), cumulo::Error);
}

// Random allocate/free against a reference: live ranges never overlap, respect alignment, and the
// allocator returns to one free range when everything is freed.
TEST(RangeAllocator, RandomizedNoOverlap) {
  std::mt19937 rng(1234);
  RangeAllocator r(1 << 20);
  struct Live {
    uint64_t off, size;
  };
  std::vector<Live> live;
  for (int i = 0; i < 5000; ++i) {
    if (live.empty() || rng() % 3 != 0) {
      uint64_t size = 1 + rng() % 5000, align = 1ull << (rng() % 9);
      auto off = r.allocate(size, align);
      if (!off) continue;
      EXPECT_EQ(*off % align, 0u);
      EXPECT_LE(*off + size, r.capacity());
      for (auto& l : live) ASSERT_TRUE(*off + size <= l.off || l.off + l.size <= *off) << "overlap at step " << i;
      live.push_back({*off, size});
    } else {
      size_t k = rng() % live.size();
      r.free(live[k].off, live[k].size);
      live.erase(live.begin() + long(k));
    }
    uint64_t sum = 0;
    for (auto& l : live) sum += l.size;
    ASSERT_EQ(r.used(), sum);
    if (i % 50 == 0) ASSERT_TRUE(r.consistent()) << "step " << i;
  }
  ASSERT_TRUE(r.consistent());
  for (auto& l : live) r.free(l.off, l.size);
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.free_range_count(), 1u);
}

namespace {
constexpr VkMemoryPropertyFlags DL = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, HV = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT,
                                HC = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, CA = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
VkPhysicalDeviceMemoryProperties table(std::initializer_list<VkMemoryPropertyFlags> types) {
  VkPhysicalDeviceMemoryProperties p{};
  for (VkMemoryPropertyFlags f : types) p.memoryTypes[p.memoryTypeCount++] = {f, 0};
  p.memoryHeapCount = 1;
  return p;
}
}  // namespace

using cumulo::gpu::MemoryUsage;
using cumulo::gpu::detail::choose_memory_type;

// A discrete GPU with a BAR window: device-local, host (coherent), host cached, device-local+host (BAR).
TEST(MemoryTypeChoice, DiscreteGpuLikeTable) {
  auto p = table({DL, HV | HC, HV | HC | CA, DL | HV | HC});
  EXPECT_EQ(choose_memory_type(p, 0xf, MemoryUsage::GpuOnly), 0);   // pure VRAM, not the BAR
  EXPECT_EQ(choose_memory_type(p, 0xf, MemoryUsage::Upload), 1);    // system memory, BAR kept for Dynamic
  EXPECT_EQ(choose_memory_type(p, 0xf, MemoryUsage::Readback), 2);  // cached for CPU reads
  EXPECT_EQ(choose_memory_type(p, 0xf, MemoryUsage::Dynamic), 3);   // BAR
  EXPECT_EQ(choose_memory_type(p, 0x1, MemoryUsage::Upload), -1);   // the resource allows only VRAM
  EXPECT_EQ(choose_memory_type(p, 0x2, MemoryUsage::GpuOnly), 1);   // falls back to what the resource allows
}

// lavapipe: a single type that is everything at once.
TEST(MemoryTypeChoice, CpuDeviceSingleType) {
  auto p = table({DL | HV | HC | CA});
  for (auto u : {MemoryUsage::GpuOnly, MemoryUsage::Upload, MemoryUsage::Readback, MemoryUsage::Dynamic})
    EXPECT_EQ(choose_memory_type(p, 0x1, u), 0);
}
