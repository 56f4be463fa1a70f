#pragma once
// Internal: the declaration as recorded by RenderGraph/PassBuilder, read by the compile steps.
#include <string>
#include <vector>

#include "engine/render/graph/render_graph.h"

namespace cumulo::render::detail {

struct ResourceDecl {
  std::string name;
  bool image = true;
  bool imported = false;
  TextureDesc texture;           // images
  BufferDesc buffer;             // buffers
  ResourceState initial, final;  // imported only
  VkImage vk_image = VK_NULL_HANDLE;
  VkImageView vk_view = VK_NULL_HANDLE;
  VkBuffer vk_buffer = VK_NULL_HANDLE;
  ResourceState* persistent = nullptr;  // import_persistent / import_history: the state to carry over
  uint32_t version = 0;  // versions handed out so far (writes declared)
};

// One read or write declared in a setup callback; `version` is the version the handle carried.
struct AccessDecl {
  uint32_t resource = 0;
  uint32_t version = 0;
  Usage usage = Usage::Sampled;
  bool read = false, write = false;
  VkPipelineStageFlags2 stages = 0;  // override of the shader stages, 0: from the queue
};

struct PassDecl {
  std::string name;
  Queue queue = Queue::Graphics;
  ExecuteFn execute;
  std::vector<AccessDecl> accesses;  // in declaration order
  bool side_effect = false;          // never culled
};

// What a usage means for synchronization (usage.cpp).
struct UsageInfo {
  VkPipelineStageFlags2 stages = 0;
  VkAccessFlags2 read_access = 0, write_access = 0;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageUsageFlags image_usage = 0;
  VkBufferUsageFlags buffer_usage = 0;
  bool can_read = false, can_write = false;
  bool images = false, buffers = false;  // which resource kinds accept this usage
  bool graphics_only = false;
};
UsageInfo usage_info(Usage usage, Queue queue, VkPipelineStageFlags2 stage_override);

constexpr VkAccessFlags2 kWriteAccessMask =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT |
    VK_ACCESS_2_MEMORY_WRITE_BIT;

}  // namespace cumulo::render::detail
