#include "engine/render/pass_helpers.h"

#include "engine/core/error.h"

namespace cumulo::render {

void set_viewport(VkCommandBuffer cmd, VkExtent3D e) {
  VkViewport vp{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
  VkRect2D sc{{0, 0}, {e.width, e.height}};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &sc);
}

void begin_rendering(PassContext& c, const Attachment* color, const Attachment* depth) {
  if (!color && !depth) fail("begin_rendering in pass '%s': no attachment", c.pass_name().c_str());
  auto info = [&c](const Attachment& a) {
    VkRenderingAttachmentInfo r{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    r.imageView = c.view(a.handle);
    r.imageLayout = c.layout(a.handle);
    r.loadOp = a.load;
    r.storeOp = a.store;
    r.clearValue = a.clear;
    return r;
  };
  VkRenderingAttachmentInfo color_info = color ? info(*color) : VkRenderingAttachmentInfo{};
  VkRenderingAttachmentInfo depth_info = depth ? info(*depth) : VkRenderingAttachmentInfo{};
  VkExtent3D e = c.extent(color ? color->handle : depth->handle);
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {e.width, e.height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = color ? 1 : 0;
  ri.pColorAttachments = color ? &color_info : nullptr;
  ri.pDepthAttachment = depth ? &depth_info : nullptr;
  vkCmdBeginRendering(c.cmd(), &ri);
  set_viewport(c.cmd(), e);
}

void add_readback_pass(RenderGraph& graph, const std::string& name,
                       const std::vector<std::pair<TextureHandle, VkBuffer>>& copies, VkDeviceSize bytes_each) {
  std::vector<std::pair<TextureHandle, BufferHandle>> handles;
  for (size_t i = 0; i < copies.size(); ++i)
    handles.emplace_back(copies[i].first, graph.import_buffer(name + "." + std::to_string(i), copies[i].second, bytes_each,
                                                             ResourceState::host_read(), ResourceState::host_read()));
  graph.add_pass(name, Queue::Compute,
      [&](PassBuilder& b) {
        for (auto& [image, buffer] : handles) {
          b.read(image, Usage::TransferSrc);
          buffer = b.write(buffer, Usage::TransferDst);
        }
        b.side_effect();
      },
      [handles](PassContext& c) {
        for (const auto& [image, buffer] : handles) {
          VkBufferImageCopy region{};
          region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
          region.imageExtent = c.extent(image);
          vkCmdCopyImageToBuffer(c.cmd(), c.image(image), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, c.buffer(buffer), 1, &region);
        }
      });
}

}  // namespace cumulo::render
