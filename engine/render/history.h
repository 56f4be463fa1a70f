#pragma once
// The GPU side of a render-graph history (graph/render_graph.h HistoryTexture): two images of a size
// relative to the output, created on first use and re-created (history invalid) when the output size
// or the format changes. A module keeps one per effect (temporal accumulation of the clouds):
//
//   render::GpuHistory history_{"cloud history", VK_FORMAT_R16G16B16A16_SFLOAT, 1.0f, usage};
//   // in add_passes:
//   HistoryHandles h = history_.import(f.ctx, f.graph);      // h.valid: false on the first frame / resize
//   ... a pass reads h.previous (if h.valid) and writes h.current ...
//   history_.invalidate();                                   // camera cut
#include <string>

#include "engine/gpu/image.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::render {

class GpuHistory {
 public:
  GpuHistory(std::string name, VkFormat format, float size_scale, VkImageUsageFlags usage);
  // Makes sure the images match the graph's output size (waits for the device when they must be
  // replaced, i.e. on a resize), then flips and imports the pair.
  HistoryHandles import(gpu::Context& ctx, RenderGraph& graph);
  void invalidate() { history_.invalidate(); }
  // A new size relative to the output (dynamic resolution): the next import replaces the images.
  void set_scale(float size_scale) { scale_ = size_scale; }
  float scale() const { return scale_; }
  void reset() { images_[0] = {}; images_[1] = {}; }  // frees the images (destroy_gpu)
  const HistoryTexture& texture() const { return history_; }

 private:
  HistoryTexture history_;
  VkFormat format_;
  float scale_;
  VkImageUsageFlags usage_;
  gpu::Image images_[2];
};

}  // namespace cumulo::render
