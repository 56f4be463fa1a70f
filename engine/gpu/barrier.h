#pragma once
// synchronization2 barriers: the one place where barrier structs are filled. The render graph's
// executor records its compiled barriers through image_barrier/buffer_barrier + cmd_barriers; code
// outside the graph (uploads, readback, tests) uses the one-barrier helpers. Inside a frame the render
// graph places barriers; a barrier recorded inside a pass should be rare and commented.
//
//   gpu::cmd_image_barrier(cmd, image.handle(), image.full_range(),
//       VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
//       VK_PIPELINE_STAGE_2_NONE, 0,
//       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
//   gpu::cmd_memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
//       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

VkImageMemoryBarrier2 image_barrier(VkImage image, const VkImageSubresourceRange& range, VkImageLayout old_layout,
                                    VkImageLayout new_layout, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
VkBufferMemoryBarrier2 buffer_barrier(VkBuffer buffer, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                      VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);  // whole buffer
// One vkCmdPipelineBarrier2 for all of them; nothing is recorded when both are empty.
void cmd_barriers(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images,
                  const std::vector<VkBufferMemoryBarrier2>& buffers = {});

void cmd_image_barrier(VkCommandBuffer cmd, VkImage image, const VkImageSubresourceRange& range,
                       VkImageLayout old_layout, VkImageLayout new_layout, VkPipelineStageFlags2 src_stage,
                       VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
void cmd_memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                        VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

}  // namespace cumulo::gpu
