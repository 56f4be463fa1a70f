// Step 2 of the cloud frame (cloud_passes.h): the march, in one pass or as the 40/60 Hz near/far split
// and its merge, sub-sampled and reconstructed when reprojection is on.
#include <string>

#include "engine/gpu/context.h"
#include "modules/clouds/render/cloud_passes.h"
#include "modules/clouds/render/reconstruct_pass.h"

namespace cumulo::clouds::render {
namespace {

// One march pass into `color` / `cdepth` (their new versions). `front` (far segment only): the near
// layer, read for its transmittance (early exit). `sub_block` > 1: rays of the `target`-sized image, one per
// block (at `sub_offset` in it).
void add_march(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, const CloudLightOutputs& light,
               TextureHandle depth, VkBuffer ubo_handle, const char* name, int segment, TextureHandle& color,
               TextureHandle& cdepth, TextureHandle front = {}, uint32_t sub_block = 1, VkExtent2D target = {},
               glm::uvec2 sub_offset = {0, 0}) {
  const CloudSettings& s = in.settings;
  const bool terrain = s.terrain_shadow && in.terrain_depth.valid();
  const TextureHandle terrain_depth = in.terrain_depth;
  const TextureHandle ms_field = light.ms_field;
  const bool solved = ms_field.valid();
  gpu::Pipeline* pipe = &res.march(s.ablation, segment, light.bc1, s.distance_noise_mip, s.light_sample_noise_mean,
                                   light.asset_slots, terrain, light.coverage_texture, solved);
  const std::vector<TextureHandle>& modelings = light.modelings;
  const std::vector<TextureHandle>& fields = light.fields;
  const std::vector<TextureHandle>& coverages = light.coverages;
  const std::vector<TextureHandle>& fairs = light.fairs;
  const TextureHandle modeling = modelings[0], field = fields[0], noise = light.noise, grid = light.grid,
                      local = light.local;
  const VkExtent2D size = target;
  CloudResources* r = &res;
  constexpr VkDeviceSize kUboSize = kParamsSize;
  graph.add_pass(name, Queue::Compute,
      [&](PassBuilder& b) {
        for (size_t a = 0; a < modelings.size(); ++a) {
          b.read(modelings[a], Usage::Sampled);
          b.read(fields[a], Usage::Sampled);
        }
        for (TextureHandle t : coverages) b.read(t, Usage::Sampled);
        for (TextureHandle t : fairs) b.read(t, Usage::Sampled);
        b.read(noise, Usage::Sampled);
        b.read(grid, Usage::Sampled);
        b.read(local, Usage::Sampled);
        b.read(depth, Usage::Sampled);
        if (front.valid()) b.read(front, Usage::Sampled);
        if (terrain) b.read(terrain_depth, Usage::Sampled);
        if (solved) b.read(ms_field, Usage::Sampled);
        color = b.write(color, Usage::StorageWrite);
        cdepth = b.write(cdepth, Usage::StorageWrite);
      },
      [r, pipe, grid, local, modeling, field, modelings, fields, coverages, fairs, noise, depth, color, cdepth, front, ubo_handle, sub_block,
       sub_offset, size, terrain, terrain_depth, solved, ms_field](PassContext& c) {
        Bindings bind(*pipe);
        bind.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
            .sampled(CLOUD_BINDING_MODELING, c.view(modeling), r->linear_clamp, c.layout(modeling))
            .sampled(CLOUD_BINDING_FIELD, c.view(field), r->linear_clamp, c.layout(field))
            .sampled(CLOUD_BINDING_NOISE, c.view(noise), r->linear_repeat, c.layout(noise))
            .sampled(CLOUD_BINDING_SCENE_DEPTH, c.view(depth), r->nearest_clamp, c.layout(depth))
            .storage(CLOUD_BINDING_OUT_COLOR, c.view(color))
            .storage(CLOUD_BINDING_OUT_DEPTH, c.view(cdepth))
            .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
            .sampled(CLOUD_BINDING_LIGHT_LOCAL, c.view(local), r->linear_clamp, c.layout(local));
        if (solved) bind.sampled(CLOUD_BINDING_MS_FIELD, c.view(ms_field), r->linear_clamp, c.layout(ms_field));
        if (front.valid()) bind.sampled(CLOUD_BINDING_NEAR_IN, c.view(front), r->nearest_clamp, c.layout(front));
        if (terrain)
          bind.sampled(CLOUD_BINDING_TERRAIN_DEPTH, c.view(terrain_depth), r->nearest_clamp, c.layout(terrain_depth));
        for (size_t a = 1; a < modelings.size(); ++a)
          bind.sampled(kModelingBinding[a], c.view(modelings[a]), r->linear_clamp, c.layout(modelings[a]))
              .sampled(kFieldBinding[a], c.view(fields[a]), r->linear_clamp, c.layout(fields[a]));
        for (size_t a = 0; a < coverages.size(); ++a)
          bind.sampled(kCoverageBinding[a], c.view(coverages[a]), r->linear_clamp, c.layout(coverages[a]));
        for (size_t a = 0; a < fairs.size(); ++a)
          bind.sampled(kFieldFairBinding[a], c.view(fairs[a]), r->linear_clamp, c.layout(fairs[a]));
        bind.push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(color);
        if (sub_block > 1) {
          // The target's rays, one per block: the image written is the sub-sampled one.
          shared::CloudMarchPush pc = target_push({size.width, size.height, 1});
          pc.sub = glm::vec4(float(sub_block), float(sub_offset.x), float(sub_offset.y), 0.0f);
          pipe->push_constants(c.cmd(), pc);
        } else {
          pipe->push_constants(c.cmd(), target_push(e));
        }
        pipe->dispatch_threads(c.cmd(), e.width, e.height);
      });
}

// The full-resolution march, sub-sampled and reconstructed when reprojection is on.
// With `merged` (the 40/60 Hz far segment, reprojected): its reconstruction merges the near layer (`front`, `front_depth`)
// in and writes `merged` instead of `cdepth`.
void add_full_res_march(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, const CloudLightOutputs& light,
                        const Reprojection& rp, TextureHandle depth, VkBuffer ubo, const char* name, int segment,
                        TextureHandle& color, TextureHandle& cdepth, TextureHandle front = {},
                        ReconstructMerged* merged = nullptr, TextureHandle front_depth = {},
                        ReconstructTemporal* temporal = nullptr) {
  const uint32_t block = rp.block;
  if (block <= 1) {
    if (temporal) *temporal = {};  // no reconstruction to accumulate in: the temporal pass does it
    return add_march(res, graph, in, light, depth, ubo, name, segment, color, cdepth, front);
  }
  const VkExtent2D size = march_extent(graph, in);
  const uint32_t sw = (size.width + block - 1) / block, sh = (size.height + block - 1) / block;
  TextureHandle sub_c = graph.create_texture("clouds.sub_color", TextureDesc::absolute(kColorFormat, sw, sh));
  TextureHandle sub_d = graph.create_texture("clouds.sub_depth", TextureDesc::absolute(kDepthFormat, sw, sh));
  add_march(res, graph, in, light, depth, ubo, name, segment, sub_c, sub_d, front, block, size, rp.sub_offset);
  TextureHandle next = rp.history.next;
  ReconstructInputs ri{res.recon_pipe, ubo, sub_c, sub_d, rp.history.prev, depth, block, rp.sub_offset, rp.history.valid,
                       rp.settled};
  if (merged) {
    ri.pipe = temporal ? res.recon_merge_temporal_pipe : res.recon_merge_pipe;
    ri.near_color = front;
    ri.near_depth = front_depth;
  } else if (temporal) {
    ri.pipe = res.recon_temporal_pipe;
  }
  add_reconstruct_pass(graph, res.ctx, merged ? "clouds.reconstruct_merge" : "clouds.reconstruct", ri, next, cdepth, merged,
                       temporal);
  color = next;
}

// The near segment at half resolution, sub-sampled and reconstructed (its rays end at the split) when its
// reprojection is on.
void add_near_march(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, const CloudLightOutputs& light,
                    const Reprojection& rp, TextureHandle depth, VkBuffer ubo, TextureHandle& color, TextureHandle& cdepth) {
  const uint32_t block = rp.near_block;
  if (block <= 1) return add_march(res, graph, in, light, depth, ubo, "clouds.march_near", CLOUD_SEGMENT_NEAR, color, cdepth);
  const VkExtent2D size = cumulo::render::relative_extent(graph.output_size(), 0.5f * in.resolution_scale);
  const uint32_t sw = (size.width + block - 1) / block, sh = (size.height + block - 1) / block;
  TextureHandle sub_c = graph.create_texture("clouds.near_sub_color", TextureDesc::absolute(kColorFormat, sw, sh));
  TextureHandle sub_d = graph.create_texture("clouds.near_sub_depth", TextureDesc::absolute(kDepthFormat, sw, sh));
  add_march(res, graph, in, light, depth, ubo, "clouds.march_near", CLOUD_SEGMENT_NEAR, sub_c, sub_d, {}, block, size,
            rp.near_offset);
  TextureHandle next = rp.near_history.next;
  add_reconstruct_pass(graph, res.ctx, "clouds.reconstruct_near",
                       {res.recon_near_pipe, ubo, sub_c, sub_d, rp.near_history.prev, depth, block, rp.near_offset,
                        rp.near_history.valid},
                       next, cdepth);
  color = next;
}

void add_split_merge(CloudResources& res, RenderGraph& graph, TextureHandle near_c, TextureHandle near_d, TextureHandle far_c,
                     TextureHandle far_d, VkBuffer ubo_handle, TextureHandle& color, TextureHandle& cdepth) {
  gpu::Pipeline* merge = res.merge_pipe;
  CloudResources* r = &res;
  graph.add_pass("clouds.split_merge", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(near_c, Usage::Sampled);
        b.read(near_d, Usage::Sampled);
        b.read(far_c, Usage::Sampled);
        b.read(far_d, Usage::Sampled);
        color = b.write(color, Usage::StorageWrite);
        cdepth = b.write(cdepth, Usage::StorageWrite);
      },
      [r, merge, near_c, near_d, far_c, far_d, color, cdepth, ubo_handle](PassContext& c) {
        Bindings(*merge)
            .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kParamsSize)
            .sampled(CLOUD_BINDING_NEAR, c.view(near_c), r->nearest_clamp, c.layout(near_c))
            .sampled(CLOUD_BINDING_NEAR_DEPTH, c.view(near_d), r->nearest_clamp, c.layout(near_d))
            .sampled(CLOUD_BINDING_FAR, c.view(far_c), r->nearest_clamp, c.layout(far_c))
            .sampled(CLOUD_BINDING_FAR_DEPTH, c.view(far_d), r->nearest_clamp, c.layout(far_d))
            .storage(CLOUD_BINDING_MERGED, c.view(color))
            .storage(CLOUD_BINDING_MERGED_DEPTH, c.view(cdepth))
            .push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(color);
        merge->push_constants(c.cmd(), target_push(e));
        merge->dispatch_threads(c.cmd(), e.width, e.height);
      });
}

bool near_segment_runs(const CloudFrameInputs& in) {
  // 40/60 Hz with no cloudscape box within the split distance (the ground view: clouds from 600 m up):
  // the near segment is empty, so its half-resolution march and the merge are skipped and the far
  // march runs over the whole ray (the same samples: none lie nearer than the split). The split
  // debug view keeps both, to show them.
  const CloudSettings& s = in.settings;
  if (!s.split) return false;
  return !(s.skip_empty_near && s.debug != CloudDebugView::Split && nearest_instance_distance(in) >= s.split_distance_m);
}

}  // namespace

Reprojection import_reprojection(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in) {
  // The marched pixel of each BxB block this frame, in the order of a Bayer matrix (each pixel once every
  // B*B frames, neighbours far apart in time).
  Reprojection rp;
  rp.block = reprojection_block(in.settings);
  if (in.camera_cut || !in.lights.empty() || res.rebuilds != res.settled_rebuilds) res.frames_settled = 0;
  else ++res.frames_settled;
  res.settled_rebuilds = res.rebuilds;
  // A whole cycle of the block since: every pixel's history was marched in the settled picture. (The near segment's
  // history keeps its clamp: the wind moves the detail of clouds within the split by pixels over a cycle.)
  rp.settled = res.frames_settled >= rp.block * rp.block;
  if (rp.block > 1) {
    if (in.camera_cut || res.recon_block != rp.block) res.recon_history.invalidate();
    res.recon_history.set_scale(in.resolution_scale);  // a new scale replaces the pair (history invalid)
    const cumulo::render::HistoryHandles h = res.recon_history.import(res.ctx, graph);
    rp.history = {h.previous, h.current, h.valid};
    rp.sub_offset = reprojection_offset(rp.block, in.frame_index);
  }
  res.recon_block = rp.block > 1 ? rp.block : 0;
  // The near segment's, when it runs (a skipped near segment leaves its history to restart).
  rp.near_runs = near_segment_runs(in);
  rp.near_block = rp.near_runs ? near_reprojection_block(in.settings) : 1;
  if (rp.near_block > 1) {
    if (in.camera_cut || res.near_block != rp.near_block) res.near_history.invalidate();
    res.near_history.set_scale(0.5f * in.resolution_scale);
    const cumulo::render::HistoryHandles h = res.near_history.import(res.ctx, graph);
    rp.near_history = {h.previous, h.current, h.valid};
    // The half-resolution pixel each block marches this frame, in the Bayer order.
    rp.near_offset = reprojection_offset(rp.near_block, in.frame_index);
  }
  res.near_block = rp.near_block > 1 ? rp.near_block : 0;
  return rp;
}

MarchOutputs add_march_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                              const CloudLightOutputs& light, const Reprojection& rp, TextureHandle depth, VkBuffer ubo,
                              const HistoryImports* temporal) {
  const CloudSettings& s = in.settings;
  MarchOutputs m;
  // The accumulation joins the reconstruction that writes the march's final colour (not the split's merge pass).
  ReconstructTemporal acc{temporal ? temporal->prev : TextureHandle{}, temporal ? temporal->next : TextureHandle{}};
  ReconstructTemporal* fuse = temporal ? &acc : nullptr;
  const float rs = in.resolution_scale;
  m.color = graph.create_texture("clouds.color", TextureDesc::relative(kColorFormat, rs));
  m.depth = graph.create_texture("clouds.depth", TextureDesc::relative(kDepthFormat, rs));
  const bool near_empty = s.split && !rp.near_runs;
  if (!s.split) {
    add_full_res_march(res, graph, in, light, rp, depth, ubo, "clouds.march", CLOUD_SEGMENT_ALL, m.color, m.depth, {},
                       nullptr, {}, fuse);
  } else if (near_empty) {
    add_full_res_march(res, graph, in, light, rp, depth, ubo, "clouds.march_far", CLOUD_SEGMENT_ALL, m.color, m.depth, {},
                       nullptr, {}, fuse);
  } else {
    TextureHandle near_c = graph.create_texture("clouds.near_color", TextureDesc::relative(kColorFormat, 0.5f * rs));
    TextureHandle near_d = graph.create_texture("clouds.near_depth", TextureDesc::relative(kDepthFormat, 0.5f * rs));
    TextureHandle far_c = graph.create_texture("clouds.far_color", TextureDesc::relative(kColorFormat, rs));
    add_near_march(res, graph, in, light, rp, depth, ubo, near_c, near_d);
    // A reprojected far segment merges the near layer in its reconstruction (one full-resolution pass less); the
    // split and profile debug views keep the merge pass, which draws them.
    if (rp.block > 1 && s.debug != CloudDebugView::Split && s.debug != CloudDebugView::Profile) {
      ReconstructMerged merged{m.color, m.depth};
      TextureHandle unused_depth;
      add_full_res_march(res, graph, in, light, rp, depth, ubo, "clouds.march_far", CLOUD_SEGMENT_FAR, far_c, unused_depth,
                         near_c, &merged, near_d, fuse);
      m.color = merged.color;
      m.depth = merged.depth;
    } else {
      TextureHandle far_d = graph.create_texture("clouds.far_depth", TextureDesc::relative(kDepthFormat, rs));
      add_full_res_march(res, graph, in, light, rp, depth, ubo, "clouds.march_far", CLOUD_SEGMENT_FAR, far_c, far_d, near_c);
      add_split_merge(res, graph, near_c, near_d, far_c, far_d, ubo, m.color, m.depth);
      fuse = nullptr;
    }
  }
  if (fuse) m.accumulated = acc.accumulated;
  return m;
}

}  // namespace cumulo::clouds::render
