#include "engine/app/frame_output.h"

#include "engine/gpu/context.h"

namespace cumulo::app {

OffscreenOutput::OffscreenOutput(gpu::Context& ctx, uint32_t w, uint32_t h)
    : image_(ctx, gpu::ImageDesc::tex2d(w, h, VK_FORMAT_R8G8B8A8_UNORM,
                                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 1, "offscreen output")) {}

render::RenderTarget OffscreenOutput::target() const {
  render::RenderTarget t;
  t.image = image_.handle();
  t.view = image_.view();
  t.format = image_.format();
  t.extent = {image_.extent().width, image_.extent().height};
  // Each frame overwrites the whole image (the previous frame finished: one frame in flight), so the
  // old contents are discarded; afterwards it is ready to be copied out.
  t.initial = render::ResourceState::undefined();
  t.final = {VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
  t.name = "offscreen output";
  return t;
}

void OffscreenOutput::after_frame() { image_.set_layout(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL); }

}  // namespace cumulo::app
