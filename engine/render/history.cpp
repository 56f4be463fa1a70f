#include "engine/render/history.h"

#include <cmath>

#include "engine/gpu/context.h"

namespace cumulo::render {

GpuHistory::GpuHistory(std::string name, VkFormat format, float size_scale, VkImageUsageFlags usage)
    : history_(std::move(name)), format_(format), scale_(size_scale), usage_(usage) {}

HistoryHandles GpuHistory::import(gpu::Context& ctx, RenderGraph& graph) {
  const VkExtent2D size = relative_extent(graph.output_size(), scale_);
  TextureDesc desc = TextureDesc::absolute(format_, size.width, size.height);
  const TextureDesc& have = history_.desc();
  if (!history_.has_images() || have.width != desc.width || have.height != desc.height || have.format != desc.format) {
    if (history_.has_images()) ctx.wait_idle();  // a resize or a new scale: frames in flight may still read the old pair
    for (int i = 0; i < 2; ++i) {
      std::string n = history_.name() + (i ? " [1]" : " [0]");
      images_[i] = gpu::Image(ctx, gpu::ImageDesc::tex2d(desc.width, desc.height, format_, usage_, 1, n.c_str()));
    }
    history_.set_images(desc, images_[0].handle(), images_[0].view(), images_[1].handle(), images_[1].view());
  }
  return graph.import_history(history_);
}

}  // namespace cumulo::render
