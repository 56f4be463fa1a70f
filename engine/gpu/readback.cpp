#include "engine/gpu/readback.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "engine/core/png.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/format.h"
#include "engine/gpu/image.h"

namespace cumulo::gpu {

float half_to_float(uint16_t h) {
  uint32_t sign = uint32_t(h & 0x8000) << 16, exp = (h >> 10) & 0x1f, mant = h & 0x3ff;
  uint32_t bits;
  if (exp == 0) {
    if (mant == 0) {
      bits = sign;
    } else {  // subnormal: renormalize
      exp = 127 - 15 + 1;
      while (!(mant & 0x400)) mant <<= 1, --exp;
      bits = sign | (exp << 23) | ((mant & 0x3ff) << 13);
    }
  } else if (exp == 31) {
    bits = sign | 0x7f800000u | (mant << 13);
  } else {
    bits = sign | ((exp + 127 - 15) << 23) | (mant << 13);
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

static float uf11_to_float(uint32_t v, int mant_bits) {  // unsigned 5-bit exponent packed floats
  uint32_t exp = v >> mant_bits, mant = v & ((1u << mant_bits) - 1);
  if (exp == 0) return std::ldexp(float(mant), -14 - mant_bits);
  if (exp == 31) return mant ? NAN : INFINITY;
  return std::ldexp(1.0f + float(mant) / float(1u << mant_bits), int(exp) - 15);
}

static uint8_t to_u8(float v, bool srgb) {
  if (!(v == v)) v = 0;  // NaN -> 0
  v = std::clamp(v, 0.0f, 1.0f);
  if (srgb) v = v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(v * 255.0f));
}

std::vector<uint8_t> convert_to_rgba8(VkFormat format, const void* texels, size_t count, bool srgb) {
  std::vector<uint8_t> out(count * 4, 255);
  const auto* b = static_cast<const uint8_t*>(texels);
  auto put = [&](size_t i, float r, float g, float bl, float a) {
    out[i * 4 + 0] = to_u8(r, srgb);
    out[i * 4 + 1] = to_u8(g, srgb);
    out[i * 4 + 2] = to_u8(bl, srgb);
    out[i * 4 + 3] = to_u8(a, false);
  };
  switch (format) {
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
      std::memcpy(out.data(), b, count * 4);
      break;
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
      for (size_t i = 0; i < count; ++i) {
        out[i * 4 + 0] = b[i * 4 + 2];
        out[i * 4 + 1] = b[i * 4 + 1];
        out[i * 4 + 2] = b[i * 4 + 0];
        out[i * 4 + 3] = b[i * 4 + 3];
      }
      break;
    case VK_FORMAT_R8_UNORM:
      for (size_t i = 0; i < count; ++i) out[i * 4 + 0] = out[i * 4 + 1] = out[i * 4 + 2] = b[i];
      break;
    case VK_FORMAT_R8G8_UNORM:
      for (size_t i = 0; i < count; ++i) out[i * 4 + 0] = b[i * 2], out[i * 4 + 1] = b[i * 2 + 1], out[i * 4 + 2] = 0;
      break;
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
      for (size_t i = 0; i < count; ++i) {
        uint32_t v;
        std::memcpy(&v, b + i * 4, 4);
        put(i, float(v & 1023) / 1023.0f, float((v >> 10) & 1023) / 1023.0f, float((v >> 20) & 1023) / 1023.0f,
            float(v >> 30) / 3.0f);
      }
      break;
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
      for (size_t i = 0; i < count; ++i) {
        uint32_t v;
        std::memcpy(&v, b + i * 4, 4);
        put(i, uf11_to_float(v & 0x7ff, 6), uf11_to_float((v >> 11) & 0x7ff, 6), uf11_to_float(v >> 22, 5), 1.0f);
      }
      break;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16_SFLOAT: {
      int n = format == VK_FORMAT_R16G16B16A16_SFLOAT ? 4 : format == VK_FORMAT_R16G16_SFLOAT ? 2 : 1;
      for (size_t i = 0; i < count; ++i) {
        float c[4] = {0, 0, 0, 1};
        for (int k = 0; k < n; ++k) {
          uint16_t h;
          std::memcpy(&h, b + (i * n + k) * 2, 2);
          c[k] = half_to_float(h);
        }
        if (n == 1) c[1] = c[2] = c[0];
        put(i, c[0], c[1], c[2], c[3]);
      }
      break;
    }
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT: {
      int n = format == VK_FORMAT_R32G32B32A32_SFLOAT ? 4 : 1;
      for (size_t i = 0; i < count; ++i) {
        float c[4] = {0, 0, 0, 1};
        std::memcpy(c, b + i * n * 4, n * 4);
        if (n == 1) c[1] = c[2] = c[0];
        put(i, c[0], c[1], c[2], c[3]);
      }
      break;
    }
    default:
      fail("gpu: no RGBA8 conversion for format %s (%d)", format_name(format), int(format));
  }
  return out;
}

std::vector<uint8_t> read_image_bytes(Context& ctx, Image& image, uint32_t mip, uint32_t layer) {
  FormatInfo fi = format_info(image.format());
  if (fi.block_bytes == 0)
    fail("gpu: readback of unsupported format %s (%d)", format_name(image.format()), int(image.format()));
  if (mip >= image.mips() || layer >= image.layers()) fail("gpu: readback of mip %u layer %u out of range", mip, layer);
  uint64_t bytes = mip_size_bytes(image.format(), image.extent(), mip);
  if (is_depth_format(image.format())) {  // only the depth aspect is copied: 2 bytes for D16, else 4
    VkExtent3D e = image.extent(mip);
    bytes = uint64_t(e.width) * e.height * e.depth *
            (image.format() == VK_FORMAT_D16_UNORM || image.format() == VK_FORMAT_D16_UNORM_S8_UINT ? 2 : 4);
  }
  Buffer staging(ctx, {.size = bytes,
                       .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       .memory = MemoryUsage::Readback,
                       .name = "image readback"});
  VkImageLayout old = image.layout();
  VkImageLayout back = old == VK_IMAGE_LAYOUT_UNDEFINED ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : old;
  VkImageAspectFlags aspect = image.aspect();
  if (aspect & VK_IMAGE_ASPECT_DEPTH_BIT) aspect = VK_IMAGE_ASPECT_DEPTH_BIT;
  ctx.submit_and_wait([&](VkCommandBuffer cmd) {
    // Whatever wrote the image in earlier submissions (shaders, attachments, copies) happens before the copy.
    cmd_image_barrier(cmd, image.handle(), image.full_range(), old, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy r{};
    r.imageSubresource = {aspect, mip, layer, 1};
    r.imageExtent = image.extent(mip);
    vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &r);
    cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    if (back != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
      cmd_image_barrier(cmd, image.handle(), image.full_range(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, back,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                        VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
  image.set_layout(back);
  std::vector<uint8_t> out(bytes);
  std::memcpy(out.data(), staging.mapped(), bytes);
  return out;
}

Rgba8Image read_image_rgba8(Context& ctx, Image& image, bool srgb_encode) {
  if (image.type() != VK_IMAGE_TYPE_2D) fail("gpu: read_image_rgba8 needs a 2D image");
  std::vector<uint8_t> raw = read_image_bytes(ctx, image, 0, 0);
  Rgba8Image out;
  out.width = image.extent().width;
  out.height = image.extent().height;
  out.pixels = convert_to_rgba8(image.format(), raw.data(), size_t(out.width) * out.height, srgb_encode);
  return out;
}

void write_png(const std::filesystem::path& path, const Rgba8Image& image) {
  if (image.pixels.size() != size_t(image.width) * image.height * 4 || image.width == 0 || image.height == 0)
    fail("%s: cannot write PNG: image is %ux%u with %zu bytes", path.string().c_str(), image.width, image.height,
         image.pixels.size());
  cumulo::write_png(path, image.pixels.data(), image.width, image.height, 4);
}

}  // namespace cumulo::gpu
