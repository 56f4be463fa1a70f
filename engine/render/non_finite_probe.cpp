#include "engine/render/non_finite_probe.h"

#include <cstring>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"

namespace cumulo::render {

namespace {
constexpr size_t kCounters = 6;  // see non_finite_probe.comp's Counters
}  // namespace

void NonFiniteProbe::create_gpu(GpuServices& g) {
  ctx_ = &g.ctx;
  count_ = &g.library.compute({.shader = "engine/non_finite_probe.comp", .defines = {{"FOLD", "0"}}, .name = "non_finite_probe"});
  fold_ = &g.library.compute({.shader = "engine/non_finite_probe.comp", .defines = {{"FOLD", "1"}}, .name = "non_finite_fold"});
  counters_ = gpu::Buffer(g.ctx, {kCounters * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUsage::Readback,
                                  "non_finite_probe counters"});
  uint32_t init[kCounters] = {0, 0, 0, 0, 0xffffffffu, 0xffffffffu};
  std::memcpy(counters_.mapped(), init, sizeof init);
}

void NonFiniteProbe::destroy_gpu() {
  counters_ = gpu::Buffer();
  count_ = fold_ = nullptr;
}

void NonFiniteProbe::add_passes(Stage stage, StageContext& f) {
  if (stage != Stage::AfterOpaque || !count_) return;
  BufferHandle counters = f.graph.import_buffer("non_finite_probe.counters", counters_.handle(), counters_.size(),
                                                ResourceState::host_read(), ResourceState::host_read());
  const TextureHandle hdr = f.hdr;
  const VkSampler nearest = f.ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
  gpu::Context* ctx = ctx_;
  gpu::Pipeline* count = count_;
  f.graph.add_pass("non_finite_probe", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(hdr, Usage::Sampled);
        counters = b.read_write(counters, Usage::StorageWrite);
        b.side_effect();
      },
      [ctx, count, hdr, counters, nearest](PassContext& c) {
        count->bind(c.cmd());
        gpu::DescriptorWriter()
            .storage_buffer(0, c.buffer(counters))
            .sampled_image(1, c.view(hdr), nearest, c.layout(hdr))
            .push(*ctx, c.cmd(), *count);
        const VkExtent3D e = c.extent(hdr);
        count->dispatch_threads(c.cmd(), e.width, e.height);
      });
  gpu::Pipeline* fold = fold_;
  f.graph.add_pass("non_finite_fold", Queue::Compute,
      [&](PassBuilder& b) {
        counters = b.read_write(counters, Usage::StorageWrite);
        b.side_effect();
      },
      [ctx, fold, counters](PassContext& c) {
        fold->bind(c.cmd());
        gpu::DescriptorWriter().storage_buffer(0, c.buffer(counters)).push(*ctx, c.cmd(), *fold);
        vkCmdDispatch(c.cmd(), 1, 1, 1);
      });
}

NonFiniteProbe::Counts NonFiniteProbe::counts() const {
  if (!counters_) return {};
  uint32_t c[kCounters];
  std::memcpy(c, counters_.mapped(), sizeof c);
  Counts r{c[3], c[1], c[2]};
  if (c[5] != 0xffffffffu) r.last_bad_pixel = glm::ivec2(int(c[5] & 0xffffu), int(c[5] >> 16));
  return r;
}

}  // namespace cumulo::render
