// Usage -> (stages, accesses, layout, creation flags): the one table every barrier comes from.
#include "engine/core/error.h"
#include "engine/render/graph/detail/graph_data.h"

namespace cumulo::render {

const char* usage_name(Usage usage) {
  switch (usage) {
    case Usage::Sampled:
      return "sampled";
    case Usage::StorageRead:
      return "storage-read";
    case Usage::StorageWrite:
      return "storage-write";
    case Usage::ColorAttachment:
      return "color-attachment";
    case Usage::DepthWrite:
      return "depth-write";
    case Usage::DepthRead:
      return "depth-read";
    case Usage::TransferSrc:
      return "transfer-src";
    case Usage::TransferDst:
      return "transfer-dst";
    case Usage::Uniform:
      return "uniform";
    case Usage::Vertex:
      return "vertex";
    case Usage::Index:
      return "index";
    case Usage::Indirect:
      return "indirect";
  }
  return "?";
}

namespace detail {

UsageInfo usage_info(Usage usage, Queue queue, VkPipelineStageFlags2 stage_override) {
  // Shader accesses happen in the compute shader of a compute pass; in a graphics pass in the
  // fragment shader unless the pass names other stages (vertex displacement, ...).
  const VkPipelineStageFlags2 shader = stage_override
                                           ? stage_override
                                           : (queue == Queue::Compute ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
                                                                      : VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  UsageInfo u;
  switch (usage) {
    case Usage::Sampled:
      u.stages = shader;
      u.read_access = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
      u.layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
      u.image_usage = VK_IMAGE_USAGE_SAMPLED_BIT;
      u.can_read = true;
      u.images = true;
      break;
    case Usage::StorageRead:
    case Usage::StorageWrite:
      u.stages = shader;
      u.read_access = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
      u.write_access = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
      u.layout = VK_IMAGE_LAYOUT_GENERAL;
      u.image_usage = VK_IMAGE_USAGE_STORAGE_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
      u.can_read = true;
      u.can_write = usage == Usage::StorageWrite;
      u.images = u.buffers = true;
      break;
    case Usage::ColorAttachment:
      u.stages = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
      u.read_access = VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
      u.write_access = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
      u.layout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      u.image_usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
      u.can_write = true;
      u.images = true;
      u.graphics_only = true;
      break;
    case Usage::DepthWrite:
    case Usage::DepthRead:
      // The combined DEPTH_STENCIL layouts are valid for depth-only formats too and need no
      // separateDepthStencilLayouts feature.
      u.stages = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
      u.read_access = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
      if (usage == Usage::DepthWrite) {
        u.write_access = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        u.layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        u.can_write = true;
      } else {
        u.layout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;
        u.can_read = true;
      }
      u.image_usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
      u.images = true;
      u.graphics_only = true;
      break;
    case Usage::TransferSrc:
      u.stages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
      u.read_access = VK_ACCESS_2_TRANSFER_READ_BIT;
      u.layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
      u.image_usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
      u.can_read = true;
      u.images = u.buffers = true;
      break;
    case Usage::TransferDst:
      u.stages = VK_PIPELINE_STAGE_2_TRANSFER_BIT;
      u.write_access = VK_ACCESS_2_TRANSFER_WRITE_BIT;
      u.layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
      u.image_usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
      u.can_write = true;
      u.images = u.buffers = true;
      break;
    case Usage::Uniform:
      u.stages = shader;
      u.read_access = VK_ACCESS_2_UNIFORM_READ_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
      u.can_read = true;
      u.buffers = true;
      break;
    case Usage::Vertex:
      u.stages = VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
      u.read_access = VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
      u.can_read = true;
      u.buffers = true;
      u.graphics_only = true;
      break;
    case Usage::Index:
      u.stages = VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT;
      u.read_access = VK_ACCESS_2_INDEX_READ_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_INDEX_BUFFER_BIT;
      u.can_read = true;
      u.buffers = true;
      u.graphics_only = true;
      break;
    case Usage::Indirect:
      u.stages = VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT;
      u.read_access = VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
      u.buffer_usage = VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
      u.can_read = true;
      u.buffers = true;
      break;
  }
  return u;
}

}  // namespace detail
}  // namespace cumulo::render
