#pragma once
// A copy of a frame's scene colour (R16G16B16A16F) to host memory, for commands that compare or average
// frames (cumulo fidelity): add_pass() in the frame's graph, read() once that frame completed.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::clouds::render {

class HdrCapture {
 public:
  explicit HdrCapture(gpu::Context& ctx) : ctx_(ctx) {}
  void add_pass(cumulo::render::RenderGraph& graph, cumulo::render::TextureHandle hdr);
  // Linear RGBA of the last completed frame, row-major, top row first.
  std::vector<glm::vec4> read() const;
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

 private:
  gpu::Context& ctx_;
  gpu::Buffer buffer_;
  uint32_t width_ = 0, height_ = 0;
};

}  // namespace cumulo::clouds::render
