#pragma once
// The offscreen output of headless runs (and of windowed screenshots), and WindowUnavailable.
#include <cstdint>
#include <stdexcept>

#include "engine/gpu/image.h"
#include "engine/gpu/vk.h"
#include "engine/render/frame_renderer.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::app {


// Thrown when a window cannot be opened (dead display, no Vulkan surface support): the caller falls
// back to headless instead of failing.
class WindowUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Headless output: an RGBA8 (UNORM; the tonemap pass encodes sRGB) image the tonemap pass writes and
// the screenshot reads back. It ends every frame in TRANSFER_SRC_OPTIMAL.
class OffscreenOutput {
 public:
  OffscreenOutput(gpu::Context& ctx, uint32_t width, uint32_t height);
  render::RenderTarget target() const;
  void after_frame();  // records the layout the graph left the image in (for readback)
  gpu::Image& image() { return image_; }

 private:
  gpu::Image image_;
};

}  // namespace cumulo::app
