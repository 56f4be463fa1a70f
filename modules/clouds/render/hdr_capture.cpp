#include "modules/clouds/render/hdr_capture.h"

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/readback.h"
#include "engine/render/pass_helpers.h"

namespace cumulo::clouds::render {

void HdrCapture::add_pass(cumulo::render::RenderGraph& graph, cumulo::render::TextureHandle hdr) {
  using namespace cumulo::render;
  const VkExtent2D size = graph.output_size();
  if (!buffer_ || width_ != size.width || height_ != size.height) {
    if (buffer_) ctx_.wait_idle();
    buffer_ = gpu::Buffer(ctx_, {VkDeviceSize(size.width) * size.height * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 gpu::MemoryUsage::Readback, "hdr capture"});
    width_ = size.width, height_ = size.height;
  }
  add_readback_pass(graph, "hdr_capture", {{hdr, buffer_.handle()}}, buffer_.size());
}

std::vector<glm::vec4> HdrCapture::read() const {
  const size_t n = size_t(width_) * height_;
  std::vector<uint16_t> halfs(n * 4);
  if (n) buffer_.download(halfs.data(), halfs.size() * 2);
  std::vector<glm::vec4> out(n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 4; ++c) out[i][c] = gpu::half_to_float(halfs[i * 4 + size_t(c)]);
  return out;
}

}  // namespace cumulo::clouds::render
