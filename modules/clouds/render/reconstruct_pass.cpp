#include "modules/clouds/render/reconstruct_pass.h"

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/core/error.h"
#include "engine/gpu/sampler.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::render {
using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::TextureHandle;
using cumulo::render::Usage;

glm::uvec2 reprojection_offset(uint32_t block, uint64_t frame_index) {
  static constexpr uint32_t kBayer4[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
  if (block <= 1) return {0, 0};
  const uint32_t k = uint32_t(frame_index % (block * block));
  // The BxB block's cells ranked by the 4x4 matrix's values (B = 3 ranks its top-left 3x3 cells).
  const uint32_t step = 4 / block;
  for (uint32_t y = 0; y < block; ++y)
    for (uint32_t x = 0; x < block; ++x) {
      const uint32_t v = kBayer4[(y * step) * 4 + x * step];
      uint32_t rank = 0;
      for (uint32_t yy = 0; yy < block; ++yy)
        for (uint32_t xx = 0; xx < block; ++xx) rank += kBayer4[(yy * step) * 4 + xx * step] < v ? 1u : 0u;
      if (rank == k) return {x, y};
    }
  return {0, 0};
}

void add_reconstruct_pass(cumulo::render::RenderGraph& graph, gpu::Context& ctx, const char* name, const ReconstructInputs& in,
                          TextureHandle& color, TextureHandle& depth, ReconstructMerged* merged,
                          ReconstructTemporal* temporal) {
  const VkSampler nearest = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
  const VkSampler linear = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  gpu::Context* c_ctx = &ctx;
  const bool merge = merged != nullptr;
  if (merge && !in.near_color.valid()) fail("%s: a merging reconstruction needs the near layer", name);
  ReconstructMerged out = merge ? *merged : ReconstructMerged{};
  const bool accumulate = temporal != nullptr;
  ReconstructTemporal acc = accumulate ? *temporal : ReconstructTemporal{};
  graph.add_pass(name, Queue::Compute,
      [&](PassBuilder& b) {
        b.read(in.sub_color, Usage::Sampled);
        b.read(in.sub_depth, Usage::Sampled);
        b.read(in.history, Usage::Sampled);
        b.read(in.scene_depth, Usage::Sampled);
        color = b.write(color, Usage::StorageWrite);
        if (merge) {
          b.read(in.near_color, Usage::Sampled);
          b.read(in.near_depth, Usage::Sampled);
          out.color = b.write(out.color, Usage::StorageWrite);
          out.depth = b.write(out.depth, Usage::StorageWrite);
        } else {
          depth = b.write(depth, Usage::StorageWrite);
        }
        if (accumulate) {
          b.read(acc.history, Usage::Sampled);
          acc.accumulated = b.write(acc.accumulated, Usage::StorageWrite);
        }
      },
      [in, c_ctx, nearest, linear, color, depth, merge, out, accumulate, acc](PassContext& c) {
        in.pipe->bind(c.cmd());
        gpu::DescriptorWriter w;
        w.uniform_buffer(CLOUD_BINDING_PARAMS, in.camera_ubo, 0, sizeof(shared::CloudParams))
            .sampled_image(CLOUD_BINDING_CURRENT, c.view(in.sub_color), nearest, c.layout(in.sub_color))
            .sampled_image(CLOUD_BINDING_CURRENT_DEPTH, c.view(in.sub_depth), nearest, c.layout(in.sub_depth))
            .sampled_image(CLOUD_BINDING_HISTORY, c.view(in.history), linear, c.layout(in.history))
            .sampled_image(CLOUD_BINDING_SCENE_DEPTH, c.view(in.scene_depth), nearest, c.layout(in.scene_depth))
            .storage_image(CLOUD_BINDING_ACCUM_OUT, c.view(color));
        if (merge)
          w.sampled_image(CLOUD_BINDING_RECON_NEAR, c.view(in.near_color), nearest, c.layout(in.near_color))
              .sampled_image(CLOUD_BINDING_RECON_NEAR_DEPTH, c.view(in.near_depth), nearest, c.layout(in.near_depth))
              .storage_image(CLOUD_BINDING_RECON_MERGED, c.view(out.color))
              .storage_image(CLOUD_BINDING_RECON_MERGED_DEPTH, c.view(out.depth));
        else
          w.storage_image(CLOUD_BINDING_OUT_DEPTH, c.view(depth));
        if (accumulate)
          w.sampled_image(CLOUD_BINDING_RECON_TEMPORAL_HISTORY, c.view(acc.history), linear, c.layout(acc.history))
              .storage_image(CLOUD_BINDING_RECON_TEMPORAL_OUT, c.view(acc.accumulated));
        w.push(*c_ctx, c.cmd(), *in.pipe);
        const VkExtent3D e = c.extent(color);
        shared::CloudMarchPush pc{};
        pc.target = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
        pc.sub = glm::vec4(float(in.block), float(in.offset.x), float(in.offset.y), in.history_valid ? (in.settled ? 2.0f : 1.0f) : 0.0f);
        in.pipe->push_constants(c.cmd(), pc);
        in.pipe->dispatch_threads(c.cmd(), e.width, e.height);
      });
  if (merge) *merged = out;
  if (accumulate) *temporal = acc;
}

}  // namespace cumulo::clouds::render
