#pragma once
// RAII image (+ its full view, + per-mip views) with suballocated memory, and CPU uploads.
//
//   auto desc = gpu::ImageDesc::tex3d(128, 128, 128, VK_FORMAT_R16G16B16A16_SFLOAT,
//                                     VK_IMAGE_USAGE_SAMPLED_BIT, /*mips=*/gpu::kAllMips, "noise");
//   gpu::Image noise(ctx, desc);
//   noise.upload({{mip0.data(), mip0.size()}, {mip1.data(), mip1.size()}, ...});  // -> SHADER_READ_ONLY_OPTIMAL
//   VkImageView v = noise.view();          // all mips; noise.mip_view(2) for one mip (storage writes)
//
//   gpu::Image target(ctx, gpu::ImageDesc::tex2d(64, 64, VK_FORMAT_R8G8B8A8_UNORM,
//                         VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 1, "target"));
//
// Aliasing (render graph): create unbound, allocate one range for several images, bind each:
//   gpu::Image a = gpu::Image::create_unbound(ctx, desc_a), b = gpu::Image::create_unbound(ctx, desc_b);
//   VkMemoryRequirements ra = a.memory_requirements(), rb = b.memory_requirements();  // combine: max size/alignment,
//   AND bits gpu::Allocation mem = ctx.allocator().allocate(combined, gpu::MemoryUsage::GpuOnly, "transient slot 0");
//   a.bind_memory(mem); b.bind_memory(mem);   // images do not own `mem`: free it after both are destroyed
//
// layout() is the last layout known to the helpers here (upload, readback); code that transitions
// the image itself (the render graph) keeps it current with set_layout() so helpers stay correct.
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "engine/gpu/allocator.h"
#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

constexpr uint32_t kAllMips = 0;  // ImageDesc::mips value: the full chain down to 1x1x1

struct ImageDesc {
  VkImageType type = VK_IMAGE_TYPE_2D;
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkExtent3D extent{1, 1, 1};
  uint32_t mips = 1;  // kAllMips: full chain
  uint32_t layers = 1;
  VkImageUsageFlags usage = 0;  // TRANSFER_DST is added for uploads when the format is not depth
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  MemoryUsage memory = MemoryUsage::GpuOnly;
  const char* name = nullptr;

  static ImageDesc tex2d(uint32_t w, uint32_t h, VkFormat f, VkImageUsageFlags usage, uint32_t mips = 1,
                         const char* name = nullptr) {
    return {VK_IMAGE_TYPE_2D, f, {w, h, 1}, mips, 1, usage, VK_SAMPLE_COUNT_1_BIT, MemoryUsage::GpuOnly, name};
  }
  static ImageDesc tex3d(uint32_t w, uint32_t h, uint32_t d, VkFormat f, VkImageUsageFlags usage, uint32_t mips = 1,
                         const char* name = nullptr) {
    return {VK_IMAGE_TYPE_3D, f, {w, h, d}, mips, 1, usage, VK_SAMPLE_COUNT_1_BIT, MemoryUsage::GpuOnly, name};
  }
};

// One mip level of CPU data: all layers tightly packed (row pitch = width in texels or blocks).
struct MipData {
  const void* data = nullptr;
  size_t bytes = 0;
};

class Image {
 public:
  Image() = default;
  Image(Context& ctx, const ImageDesc& desc);  // creates, allocates, binds, creates the full view
  static Image create_unbound(Context& ctx, const ImageDesc& desc);
  ~Image() { reset(); }
  Image(Image&& o) noexcept { *this = std::move(o); }
  Image& operator=(Image&& o) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;
  void reset();
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

  VkMemoryRequirements memory_requirements() const;
  // Binds an allocation the image does not own (aliasing); creates the full view.
  void bind_memory(const Allocation& allocation, VkDeviceSize offset = 0);

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }  // null for transfer-only images
  VkImageView mip_view(uint32_t mip);         // single-mip view (all layers), created on first use
  VkFormat format() const { return desc_.format; }
  VkExtent3D extent() const { return desc_.extent; }
  VkExtent3D extent(uint32_t mip) const;
  uint32_t mips() const { return desc_.mips; }
  uint32_t layers() const { return desc_.layers; }
  VkImageType type() const { return desc_.type; }
  const ImageDesc& desc() const { return desc_; }
  VkImageAspectFlags aspect() const;
  VkImageSubresourceRange full_range() const { return {aspect(), 0, desc_.mips, 0, desc_.layers}; }
  VkImageLayout layout() const { return layout_; }
  void set_layout(VkImageLayout layout) { layout_ = layout; }

  // Uploads every mip from CPU data (sizes must match mip_size_bytes * layers exactly) through one
  // staging buffer, then leaves the image in `final_layout` visible to all later commands. Waits.
  void upload(std::span<const MipData> mips, VkImageLayout final_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  void upload(std::initializer_list<MipData> mips,
              VkImageLayout final_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL) {
    upload(std::span<const MipData>(mips.begin(), mips.size()), final_layout);
  }
  // A 1x1 sampled 2D image holding one texel (`texel`: its bytes in `format`): the stand-in bound where a pass reads a
  // map that a frame may not have (no shadow: a transmittance of 1; no occluder: the far depth).
  static Image single_texel(Context& ctx, VkFormat format, const void* texel, size_t bytes, const char* name) {
    Image img(ctx, ImageDesc::tex2d(1, 1, format, VK_IMAGE_USAGE_SAMPLED_BIT, 1, name));
    img.upload({{texel, bytes}});
    return img;
  }
  // Fills mips 1..n-1 from mip 0 with linear blits (2D or 3D box-filter downsampling), leaving the
  // whole image in `final_layout`. Mip 0 must hold data in layout(). Needs a format with linear
  // blit support (checked: throws otherwise).
  void cmd_generate_mips(VkCommandBuffer cmd, VkImageLayout final_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // Records a transition from layout() to `layout` (full range, conservative ALL_COMMANDS scopes) and updates layout().
  void cmd_transition(VkCommandBuffer cmd, VkImageLayout layout);

 private:
  void create(Context& ctx, const ImageDesc& desc);
  VkImageView make_view(uint32_t base_mip, uint32_t mip_count) const;

  Context* ctx_ = nullptr;
  ImageDesc desc_;    // desc_.name points into name_ (the caller's may not outlive the image)
  std::string name_;  // for messages about the image after its creation (its upload's staging memory)
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  std::vector<VkImageView> mip_views_;
  Allocation allocation_;  // empty for images bound to someone else's allocation
  VkImageLayout layout_ = VK_IMAGE_LAYOUT_UNDEFINED;
};

}  // namespace cumulo::gpu
