#pragma once
// Format facts needed for uploads and readback (texel block size, compression, aspect).
//
//   gpu::FormatInfo f = gpu::format_info(VK_FORMAT_BC1_RGBA_UNORM_BLOCK);  // {8 bytes, 4x4 block}
//   uint64_t bytes = gpu::mip_size_bytes(VK_FORMAT_R16G16B16A16_SFLOAT, {128, 128, 128}, 2);
#include <cstdint>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

struct FormatInfo {
  uint32_t block_bytes = 0;  // bytes per texel, or per block for compressed formats; 0 = unknown
  uint32_t block_width = 1, block_height = 1;
  uint32_t channels = 0;
  bool compressed() const { return block_width > 1; }
};

FormatInfo format_info(VkFormat format);  // block_bytes == 0 for formats we do not handle
const char* format_name(VkFormat format);
bool is_depth_format(VkFormat format);
bool has_stencil(VkFormat format);
VkImageAspectFlags format_aspect(VkFormat format);
VkExtent3D mip_extent(VkExtent3D base, uint32_t mip);
// Tightly packed size of one layer of mip `mip` (compressed formats round up to whole blocks).
uint64_t mip_size_bytes(VkFormat format, VkExtent3D base, uint32_t mip);
uint32_t max_mip_count(VkExtent3D extent);

}  // namespace cumulo::gpu
