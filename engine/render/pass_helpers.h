#pragma once
// Helpers that keep a pass's record callback short: dynamic rendering on graph attachments in the
// layouts the graph chose, viewport + scissor for any target size (half-resolution passes), and
// compute group counts.
//
//   begin_rendering(c, {hdr, VK_ATTACHMENT_LOAD_OP_LOAD}, &depth_att);  ... vkCmdEndRendering(c.cmd());
//   set_viewport(c.cmd(), c.extent(half_res));
//   vkCmdDispatch(c.cmd(), groups(e.width, 8), groups(e.height, 8), 1);
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/render/graph/render_graph.h"

namespace cumulo::render {

struct Attachment {
  TextureHandle handle;
  VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_LOAD;
  VkAttachmentStoreOp store = VK_ATTACHMENT_STORE_OP_STORE;
  VkClearValue clear{};
};

// Begins dynamic rendering over the colour target's extent (or the depth's when color is null), in the
// layouts the render graph chose for this pass, and sets the full viewport and scissor.
void begin_rendering(PassContext& c, const Attachment* color, const Attachment* depth = nullptr);
inline void begin_rendering(PassContext& c, const Attachment& color, const Attachment* depth = nullptr) {
  begin_rendering(c, &color, depth);
}
// Viewport (depth 0..1) and scissor covering `extent`.
void set_viewport(VkCommandBuffer cmd, VkExtent3D extent);
// A side-effect pass named `name` copying mip 0 of each image into its host-visible buffer (imported per
// frame in host_read state): the image's texels, tightly packed, once the frame completed.
void add_readback_pass(RenderGraph& graph, const std::string& name,
                       const std::vector<std::pair<TextureHandle, VkBuffer>>& copies, VkDeviceSize bytes_each);
// Work groups covering `size` items with `local` items per group.
constexpr uint32_t groups(uint32_t size, uint32_t local) { return (size + local - 1) / local; }

}  // namespace cumulo::render
