#pragma once
// What the process holds on the device right now: live Vulkan objects by kind and device memory by the name its
// resource was created with. The soak (`cumulo soak`) samples both every window of frames: a count that grows while
// the camera loops over the same path is a leak. Counted where the objects are made and destroyed (buffer.cpp,
// image.cpp, pipeline.cpp, descriptors.cpp, allocator.cpp), for every context of the process.
//
//   const gpu::LiveObjects now = gpu::live_objects();   // images, buffers, pipelines, descriptor pools and sets
//   for (auto& [name, bytes] : gpu::live_memory_by_name()) ...
#include <cstdint>
#include <map>
#include <string>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

struct LiveObjects {
  int64_t images = 0, buffers = 0, pipelines = 0, descriptor_pools = 0, descriptor_sets = 0;
};
LiveObjects live_objects();

// Device memory held per resource name (allocations without a name under "(unnamed)"), summed over the live
// suballocations of every allocator.
std::map<std::string, uint64_t> live_memory_by_name();

namespace detail {
enum class LiveKind { Image, Buffer, Pipeline, DescriptorPool, DescriptorSet };
void count_live(LiveKind kind, int64_t delta);
void note_allocation(VkDeviceMemory memory, VkDeviceSize offset, VkDeviceSize size, const char* name);
void note_free(VkDeviceMemory memory, VkDeviceSize offset);
}  // namespace detail

}  // namespace cumulo::gpu
