#pragma once
// Shared by the noise GPU test and the fetch benchmark: the Vulkan format of a noise volume, its
// support on the device, and the upload of every mip of a clouds::Volume (header-only: test code).
//
// R4G4B4A4: our word (R in bits 12-15, G 8-11, B 4-7, A 0-3, little endian) is exactly
// VK_FORMAT_R4G4B4A4_UNORM_PACK16, but that format's sampling support is optional and lavapipe lacks
// it, while VK_FORMAT_B4G4R4A4_UNORM_PACK16 (B in 12-15 ... ) must be sampleable with linear filtering
// on every Vulkan device. So the same bytes go into a B4G4R4A4 image viewed with the swizzle
// r <- b, b <- r: shaders read .rgba as written.
#include <memory>
#include <vector>

#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/image.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::clouds::test {

// Sampled + linear filtering + transfer destination with optimal tiling: what a 3D noise texture needs.
inline bool noise_format_supported(const gpu::Context& ctx, VkFormat format) {
  VkFormatProperties props{};
  vkGetPhysicalDeviceFormatProperties(ctx.physical_device(), format, &props);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
  return (props.optimalTilingFeatures & need) == need;
}

struct NoiseGpuFormat {
  VkFormat format = VK_FORMAT_UNDEFINED;
  bool swap_red_blue = false;  // view swizzle r <- b, b <- r
};

inline NoiseGpuFormat noise_gpu_format(const gpu::Context& ctx, VolumeEncoding e) {
  if (e == VolumeEncoding::RGBA8) return {VK_FORMAT_R8G8B8A8_UNORM, false};
  if (e != VolumeEncoding::R4G4B4A4) fail("noise on the GPU: unexpected encoding %s", encoding_name(e));
  if (noise_format_supported(ctx, VK_FORMAT_R4G4B4A4_UNORM_PACK16)) return {VK_FORMAT_R4G4B4A4_UNORM_PACK16, false};
  return {VK_FORMAT_B4G4R4A4_UNORM_PACK16, true};
}

// The image plus the view shaders should use (the image's own view, or an owned swizzled one).
class NoiseImage {
 public:
  NoiseImage(gpu::Context& ctx, const Volume& v, const char* name) : device_(ctx.device()) {
    format_ = noise_gpu_format(ctx, v.encoding);
    image_ = gpu::Image(ctx, gpu::ImageDesc::tex3d(v.size.x, v.size.y, v.size.z, format_.format,
                                                   VK_IMAGE_USAGE_SAMPLED_BIT, v.mip_count(), name));
    upload(ctx, v);
    if (format_.swap_red_blue) {
      VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
      info.image = image_.handle();
      info.viewType = VK_IMAGE_VIEW_TYPE_3D;
      info.format = format_.format;
      info.components = {VK_COMPONENT_SWIZZLE_B, VK_COMPONENT_SWIZZLE_G, VK_COMPONENT_SWIZZLE_R, VK_COMPONENT_SWIZZLE_A};
      info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, v.mip_count(), 0, 1};
      if (vkCreateImageView(device_, &info, nullptr, &swizzled_) != VK_SUCCESS) fail("%s: cannot create the swizzled view", name);
      ctx.set_name(swizzled_, name);
    }
  }
  ~NoiseImage() {
    if (swizzled_) vkDestroyImageView(device_, swizzled_, nullptr);
  }
  NoiseImage(const NoiseImage&) = delete;
  NoiseImage& operator=(const NoiseImage&) = delete;

  VkImageView view() const { return swizzled_ ? swizzled_ : image_.view(); }
  const NoiseGpuFormat& format() const { return format_; }

 private:
  // gpu::Image::upload does not know the 16-bit packed formats (engine/gpu/format.cpp), so the same
  // staging copy is recorded here: every level's bytes exactly as the Volume holds them.
  void upload(gpu::Context& ctx, const Volume& v) {
    uint64_t total = 0;
    std::vector<uint64_t> offsets;
    for (const auto& level : v.levels) {
      total = (total + 15) & ~15ull;
      offsets.push_back(total);
      total += level.size();
    }
    gpu::Buffer staging(ctx, {.size = total, .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                              .memory = gpu::MemoryUsage::Upload, .name = "noise staging"});
    std::vector<VkBufferImageCopy> regions;
    for (uint32_t m = 0; m < v.mip_count(); ++m) {
      std::memcpy(staging.mapped_as<char>() + offsets[m], v.levels[m].data(), v.levels[m].size());
      VkBufferImageCopy r{};
      r.bufferOffset = offsets[m];
      r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, m, 0, 1};
      glm::uvec3 e = v.level_size(m);
      r.imageExtent = {e.x, e.y, e.z};
      regions.push_back(r);
    }
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, v.mip_count(), 0, 1};
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
      gpu::cmd_image_barrier(cmd, image_.handle(), range, VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                             VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      vkCmdCopyBufferToImage(cmd, staging.handle(), image_.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             static_cast<uint32_t>(regions.size()), regions.data());
      gpu::cmd_image_barrier(cmd, image_.handle(), range, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                             VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                             VK_ACCESS_2_MEMORY_READ_BIT);
    });
    image_.set_layout(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  }

  VkDevice device_;
  NoiseGpuFormat format_;
  gpu::Image image_;
  VkImageView swizzled_ = VK_NULL_HANDLE;
};

}  // namespace cumulo::clouds::test
