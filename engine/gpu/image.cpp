#include "engine/gpu/image.h"

#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/format.h"
#include "engine/gpu/live_objects.h"

namespace cumulo::gpu {

void Image::create(Context& ctx, const ImageDesc& desc) {
  ctx_ = &ctx;
  desc_ = desc;
  name_ = desc.name ? desc.name : "";
  desc_.name = name_.c_str();
  const char* name = desc.name ? desc.name : "(unnamed)";
  if (desc.extent.width == 0 || desc.extent.height == 0 || desc.extent.depth == 0)
    fail("gpu: image '%s' has a zero extent %ux%ux%u", name, desc.extent.width, desc.extent.height, desc.extent.depth);
  if (desc_.mips == kAllMips) desc_.mips = max_mip_count(desc.extent);
  desc_.name = nullptr;  // not owned
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = desc.type;
  info.format = desc.format;
  info.extent = desc.extent;
  info.mipLevels = desc_.mips;
  info.arrayLayers = desc.layers;
  info.samples = desc.samples;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  // Transfer usage is added so upload/readback helpers always work, unless the format refuses it.
  VkImageFormatProperties fp;
  info.usage = desc.usage | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  VkResult r = vkGetPhysicalDeviceImageFormatProperties(ctx.physical_device(), info.format, info.imageType, info.tiling,
                                                        info.usage, 0, &fp);
  if (r != VK_SUCCESS) {
    info.usage = desc.usage;
    r = vkGetPhysicalDeviceImageFormatProperties(ctx.physical_device(), info.format, info.imageType, info.tiling,
                                                 info.usage, 0, &fp);
  }
  if (r != VK_SUCCESS)
    fail("gpu: image '%s': format %s (%d) with usage 0x%x is not supported as a %uD image on %s", name,
         format_name(desc.format), int(desc.format), info.usage, desc.type == VK_IMAGE_TYPE_3D ? 3u : 2u,
         ctx.info().name.c_str());
  if (desc.extent.width > fp.maxExtent.width || desc.extent.height > fp.maxExtent.height ||
      desc.extent.depth > fp.maxExtent.depth || desc_.mips > fp.maxMipLevels || desc.layers > fp.maxArrayLayers)
    fail("gpu: image '%s': %ux%ux%u with %u mips and %u layers exceeds the device limits for %s", name,
         desc.extent.width, desc.extent.height, desc.extent.depth, desc_.mips, desc.layers, format_name(desc.format));
  desc_.usage = info.usage;
  VK_CHECK(vkCreateImage(ctx.device(), &info, nullptr, &image_));
  detail::count_live(detail::LiveKind::Image, 1);
  if (desc.name) ctx.set_name(image_, desc.name);
}

Image::Image(Context& ctx, const ImageDesc& desc) {
  create(ctx, desc);
  VkMemoryRequirements req = memory_requirements();
  try {
    allocation_ = ctx.allocator().allocate(req, desc.memory, desc.name);
    bind_memory(allocation_);
  } catch (...) {
    reset();
    throw;
  }
  if (desc.name && view_) ctx.set_name(view_, desc.name);
}

Image Image::create_unbound(Context& ctx, const ImageDesc& desc) {
  Image img;
  img.create(ctx, desc);
  return img;
}

VkMemoryRequirements Image::memory_requirements() const {
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx_->device(), image_, &req);
  return req;
}

void Image::bind_memory(const Allocation& a, VkDeviceSize offset) {
  VK_CHECK(vkBindImageMemory(ctx_->device(), image_, a.memory, a.offset + offset));
  // Transfer-only images cannot have views (VUID-VkImageViewCreateInfo-image-04441).
  const VkImageUsageFlags viewable = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                     VK_IMAGE_USAGE_INPUT_ATTACHMENT_BIT;
  if (desc_.usage & viewable) view_ = make_view(0, desc_.mips);
}

Image& Image::operator=(Image&& o) noexcept {
  if (this != &o) {
    reset();
    ctx_ = o.ctx_;
    desc_ = o.desc_;
    name_ = std::move(o.name_);
    desc_.name = name_.c_str();
    image_ = o.image_;
    view_ = o.view_;
    mip_views_ = std::move(o.mip_views_);
    allocation_ = o.allocation_;
    layout_ = o.layout_;
    o.image_ = VK_NULL_HANDLE;
    o.view_ = VK_NULL_HANDLE;
    o.mip_views_.clear();
    o.allocation_ = Allocation{};
  }
  return *this;
}

void Image::reset() {
  if (!ctx_) return;
  for (VkImageView v : mip_views_)
    if (v) vkDestroyImageView(ctx_->device(), v, nullptr);
  mip_views_.clear();
  if (view_) vkDestroyImageView(ctx_->device(), view_, nullptr);
  if (image_) {
    vkDestroyImage(ctx_->device(), image_, nullptr);
    detail::count_live(detail::LiveKind::Image, -1);
  }
  if (allocation_) ctx_->allocator().free(allocation_);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  layout_ = VK_IMAGE_LAYOUT_UNDEFINED;
}

VkImageAspectFlags Image::aspect() const { return format_aspect(desc_.format); }

VkExtent3D Image::extent(uint32_t mip) const { return mip_extent(desc_.extent, mip); }

VkImageView Image::make_view(uint32_t base_mip, uint32_t mip_count) const {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image_;
  if (desc_.type == VK_IMAGE_TYPE_3D)
    info.viewType = VK_IMAGE_VIEW_TYPE_3D;
  else if (desc_.type == VK_IMAGE_TYPE_1D)
    info.viewType = desc_.layers > 1 ? VK_IMAGE_VIEW_TYPE_1D_ARRAY : VK_IMAGE_VIEW_TYPE_1D;
  else
    info.viewType = desc_.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
  info.format = desc_.format;
  // Depth+stencil images are viewed through depth only (sampling needs a single aspect).
  VkImageAspectFlags a = aspect();
  if (a & VK_IMAGE_ASPECT_DEPTH_BIT) a = VK_IMAGE_ASPECT_DEPTH_BIT;
  info.subresourceRange = {a, base_mip, mip_count, 0, desc_.layers};
  VkImageView v;
  VK_CHECK(vkCreateImageView(ctx_->device(), &info, nullptr, &v));
  return v;
}

VkImageView Image::mip_view(uint32_t mip) {
  if (mip >= desc_.mips) fail("gpu: mip_view(%u) of an image with %u mips", mip, desc_.mips);
  if (mip_views_.empty()) mip_views_.resize(desc_.mips, VK_NULL_HANDLE);
  if (!mip_views_[mip]) mip_views_[mip] = make_view(mip, 1);
  return mip_views_[mip];
}

void Image::cmd_transition(VkCommandBuffer cmd, VkImageLayout layout) {
  cmd_image_barrier(cmd, image_, full_range(), layout_, layout, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  layout_ = layout;
}

void Image::upload(std::span<const MipData> mips, VkImageLayout final_layout) {
  FormatInfo fi = format_info(desc_.format);
  if (fi.block_bytes == 0)
    fail("gpu: upload to an image of unsupported format %s (%d)", format_name(desc_.format), int(desc_.format));
  if (mips.empty() || mips.size() > desc_.mips)
    fail("gpu: upload of %zu mips to an image with %u mips", mips.size(), desc_.mips);
  uint64_t total = 0;
  std::vector<uint64_t> offsets;
  for (uint32_t m = 0; m < mips.size(); ++m) {
    uint64_t want = mip_size_bytes(desc_.format, desc_.extent, m) * desc_.layers;
    if (mips[m].bytes != want)
      fail("gpu: upload mip %u: got %zu bytes, a %ux%ux%u %s mip needs %llu", m, mips[m].bytes, extent(m).width,
           extent(m).height, extent(m).depth, format_name(desc_.format), (unsigned long long)want);
    total = (total + 15) & ~15ull;  // texel-block aligned offsets for every format we know
    offsets.push_back(total);
    total += want;
  }
  const std::string staging_name = (name_.empty() ? std::string("an image") : name_) + " (upload staging)";
  Buffer staging(*ctx_, {.size = total,
                         .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                         .memory = MemoryUsage::Upload,
                         .name = staging_name.c_str()});
  std::vector<VkBufferImageCopy> regions;
  for (uint32_t m = 0; m < mips.size(); ++m) {
    std::memcpy(staging.mapped_as<char>() + offsets[m], mips[m].data, mips[m].bytes);
    VkBufferImageCopy r{};
    r.bufferOffset = offsets[m];
    r.imageSubresource = {aspect(), m, 0, desc_.layers};
    r.imageExtent = extent(m);
    regions.push_back(r);
  }
  ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
    // Previous contents are discarded (UNDEFINED), but earlier GPU accesses still must finish first.
    cmd_image_barrier(cmd, image_, full_range(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdCopyBufferToImage(cmd, staging.handle(), image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           uint32_t(regions.size()), regions.data());
    cmd_image_barrier(cmd, image_, full_range(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
  layout_ = final_layout;
}

}  // namespace cumulo::gpu

namespace cumulo::gpu {

void Image::cmd_generate_mips(VkCommandBuffer cmd, VkImageLayout final_layout) {
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(ctx_->physical_device(), desc_.format, &fp);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_BLIT_SRC_BIT | VK_FORMAT_FEATURE_BLIT_DST_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
  if ((fp.optimalTilingFeatures & need) != need)
    fail("gpu: cannot generate mips for format %s: no linear blit support on %s", format_name(desc_.format),
         ctx_->info().name.c_str());
  VkImageAspectFlags a = aspect();
  // Mip 0 -> TRANSFER_SRC (after whatever wrote it); mips 1.. -> TRANSFER_DST (contents discarded).
  cmd_image_barrier(cmd, image_, {a, 0, 1, 0, desc_.layers}, layout_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
  if (desc_.mips > 1)
    cmd_image_barrier(cmd, image_, {a, 1, desc_.mips - 1, 0, desc_.layers}, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                      VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  for (uint32_t m = 1; m < desc_.mips; ++m) {
    VkExtent3D s = extent(m - 1), d = extent(m);
    VkImageBlit blit{};
    blit.srcSubresource = {a, m - 1, 0, desc_.layers};
    blit.srcOffsets[1] = {int32_t(s.width), int32_t(s.height), int32_t(s.depth)};
    blit.dstSubresource = {a, m, 0, desc_.layers};
    blit.dstOffsets[1] = {int32_t(d.width), int32_t(d.height), int32_t(d.depth)};
    vkCmdBlitImage(cmd, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &blit, VK_FILTER_LINEAR);
    // The mip just written becomes the next source.
    cmd_image_barrier(cmd, image_, {a, m, 1, 0, desc_.layers}, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_BLIT_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  }
  cmd_image_barrier(cmd, image_, full_range(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, final_layout,
                    VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  layout_ = final_layout;
}

}  // namespace cumulo::gpu
