#pragma once
// Renders one frame of a FrameRenderer into an RGBA8 offscreen image and reads it back: how the
// renderer tests (engine and modules) look at what a snapshot draws.
#include "engine/gpu/context.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/gpu/readback.h"
#include "engine/render/frame_renderer.h"

namespace cumulo::test {

inline gpu::Rgba8Image render_offscreen(gpu::Context& ctx, render::FrameRenderer& renderer,
                                        const render::FrameSnapshot& s) {
  gpu::Image out(ctx, gpu::ImageDesc::tex2d(s.width, s.height, VK_FORMAT_R8G8B8A8_UNORM,
                                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, 1,
                                            "test output"));
  render::RenderTarget t;
  t.image = out.handle();
  t.view = out.view();
  t.format = out.format();
  t.extent = {s.width, s.height};
  t.initial = render::ResourceState::undefined();
  t.final = {VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT};
  gpu::FrameRing ring(ctx, 1);
  gpu::Frame& f = ring.begin();
  renderer.record_frame(f.cmd, s, t, f.slot);
  ring.submit(f);
  ring.wait_all();
  out.set_layout(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  return gpu::read_image_rgba8(ctx, out);
}

}  // namespace cumulo::test
