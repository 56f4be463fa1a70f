#include "engine/gpu/format.h"

#include <algorithm>

namespace cumulo::gpu {

FormatInfo format_info(VkFormat f) {
  switch (f) {
    case VK_FORMAT_R8_UNORM:
    case VK_FORMAT_R8_SNORM:
    case VK_FORMAT_R8_UINT:
    case VK_FORMAT_R8_SINT:
    case VK_FORMAT_R8_SRGB:
      return {1, 1, 1, 1};
    case VK_FORMAT_R8G8_UNORM:
    case VK_FORMAT_R8G8_SNORM:
    case VK_FORMAT_R8G8_UINT:
      return {2, 1, 1, 2};
    case VK_FORMAT_R16_UNORM:
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_R16_SNORM:
      return {2, 1, 1, 1};
    case VK_FORMAT_D16_UNORM:
      return {2, 1, 1, 1};
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R8G8B8A8_SNORM:
    case VK_FORMAT_R8G8B8A8_UINT:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
      return {4, 1, 1, 4};
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
    case VK_FORMAT_A2R10G10B10_UNORM_PACK32:
      return {4, 1, 1, 4};
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
    case VK_FORMAT_E5B9G9R9_UFLOAT_PACK32:
      return {4, 1, 1, 3};
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16_UNORM:
    case VK_FORMAT_R16G16_SNORM:
      return {4, 1, 1, 2};
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SINT:
      return {4, 1, 1, 1};
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D24_UNORM_S8_UINT:
      return {4, 1, 1, 1};
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return {8, 1, 1, 2};
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_UNORM:
    case VK_FORMAT_R16G16B16A16_SNORM:
    case VK_FORMAT_R16G16B16A16_UINT:
      return {8, 1, 1, 4};
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT:
      return {8, 1, 1, 2};
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
      return {16, 1, 1, 4};
    case VK_FORMAT_BC1_RGB_UNORM_BLOCK:
    case VK_FORMAT_BC1_RGB_SRGB_BLOCK:
    case VK_FORMAT_BC1_RGBA_UNORM_BLOCK:
    case VK_FORMAT_BC1_RGBA_SRGB_BLOCK:
      return {8, 4, 4, 4};
    case VK_FORMAT_BC4_UNORM_BLOCK:
    case VK_FORMAT_BC4_SNORM_BLOCK:
      return {8, 4, 4, 1};
    case VK_FORMAT_BC2_UNORM_BLOCK:
    case VK_FORMAT_BC3_UNORM_BLOCK:
    case VK_FORMAT_BC3_SRGB_BLOCK:
      return {16, 4, 4, 4};
    case VK_FORMAT_BC5_UNORM_BLOCK:
    case VK_FORMAT_BC5_SNORM_BLOCK:
      return {16, 4, 4, 2};
    case VK_FORMAT_BC6H_UFLOAT_BLOCK:
    case VK_FORMAT_BC6H_SFLOAT_BLOCK:
      return {16, 4, 4, 3};
    case VK_FORMAT_BC7_UNORM_BLOCK:
    case VK_FORMAT_BC7_SRGB_BLOCK:
      return {16, 4, 4, 4};
    default:
      return {};
  }
}

const char* format_name(VkFormat f) {
  switch (f) {
#define CASE(x)       \
  case VK_FORMAT_##x: \
    return #x;
    CASE(R8_UNORM)
    CASE(R8G8_UNORM)
    CASE(R16_SFLOAT)
    CASE(R16_UNORM)
    CASE(R8G8B8A8_UNORM)
    CASE(R8G8B8A8_SRGB)
    CASE(B8G8R8A8_UNORM) CASE(B8G8R8A8_SRGB) CASE(A2B10G10R10_UNORM_PACK32) CASE(B10G11R11_UFLOAT_PACK32)
        CASE(R16G16_SFLOAT) CASE(R32_SFLOAT) CASE(R32_UINT) CASE(D32_SFLOAT) CASE(D24_UNORM_S8_UINT) CASE(D16_UNORM)
            CASE(R16G16B16A16_SFLOAT) CASE(R16G16B16A16_UNORM) CASE(R32G32_SFLOAT) CASE(R32G32B32A32_SFLOAT)
                CASE(BC1_RGBA_UNORM_BLOCK) CASE(BC1_RGB_UNORM_BLOCK) CASE(BC4_UNORM_BLOCK) CASE(BC5_UNORM_BLOCK)
                    CASE(BC6H_UFLOAT_BLOCK) CASE(BC7_UNORM_BLOCK)
#undef CASE
                        default : return "VK_FORMAT_(other)";
  }
}

bool is_depth_format(VkFormat f) {
  return f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_X8_D24_UNORM_PACK32 ||
         f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_D16_UNORM_S8_UINT;
}

bool has_stencil(VkFormat f) {
  return f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_D16_UNORM_S8_UINT ||
         f == VK_FORMAT_S8_UINT;
}

VkImageAspectFlags format_aspect(VkFormat f) {
  if (!is_depth_format(f)) return f == VK_FORMAT_S8_UINT ? VK_IMAGE_ASPECT_STENCIL_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
  return VK_IMAGE_ASPECT_DEPTH_BIT | (has_stencil(f) ? VK_IMAGE_ASPECT_STENCIL_BIT : 0);
}

VkExtent3D mip_extent(VkExtent3D b, uint32_t mip) {
  return {std::max(1u, b.width >> mip), std::max(1u, b.height >> mip), std::max(1u, b.depth >> mip)};
}

uint64_t mip_size_bytes(VkFormat format, VkExtent3D base, uint32_t mip) {
  FormatInfo fi = format_info(format);
  VkExtent3D e = mip_extent(base, mip);
  uint64_t bw = (e.width + fi.block_width - 1) / fi.block_width,
           bh = (e.height + fi.block_height - 1) / fi.block_height;
  return bw * bh * e.depth * fi.block_bytes;
}

uint32_t max_mip_count(VkExtent3D e) {
  uint32_t m = std::max({e.width, e.height, e.depth}), n = 1;
  while (m > 1) m >>= 1, ++n;
  return n;
}

}  // namespace cumulo::gpu
