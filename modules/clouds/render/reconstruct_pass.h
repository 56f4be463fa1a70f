#pragma once
// The reprojection of a sub-sampled march (shaders/clouds/reconstruct.comp; 2015 talk: 1 of 16 pixels per
// frame), shared by the voxel clouds' full-resolution march and the 2.5D sky: which pixel of each BxB
// block is marched this frame, and the pass that rebuilds the whole image from it and last frame's.
#include <cstdint>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

// The marched pixel of each BxB block (B = 2, 3 or 4) in frame `frame_index`: Bayer order, each pixel once
// every B*B frames, neighbours far apart in time.
glm::uvec2 reprojection_offset(uint32_t block, uint64_t frame_index);

struct ReconstructInputs {
  gpu::Pipeline* pipe = nullptr;   // clouds/reconstruct.comp
  VkBuffer camera_ubo = VK_NULL_HANDLE;  // a shared::CloudParams block: its view_proj, inv_view_proj, prev_view_proj, camera_pos
  cumulo::render::TextureHandle sub_color, sub_depth;  // this frame's marched pixels
  cumulo::render::TextureHandle history;               // last frame's reconstruction
  cumulo::render::TextureHandle scene_depth;
  uint32_t block = 4;
  glm::uvec2 offset{0, 0};
  bool history_valid = false;
  // The picture has not changed in ways the reprojection cannot follow for a whole cycle of the block (no camera cut,
  // no point light, no light-grid rebuild: CloudResources::frames_settled): a pixel whose history lands exactly on a
  // texel (a still camera) keeps it unclamped.
  bool settled = false;
  // The 40/60 Hz far segment's merge (add_reconstruct_pass with `merged`): the near layer at half resolution
  // (reconstruct.comp's MERGE_NEAR; `pipe` is that variant).
  cumulo::render::TextureHandle near_color, near_depth;
};

// What a merging reconstruction writes besides the history.
struct ReconstructMerged {
  cumulo::render::TextureHandle color, depth;
};

// An accumulating reconstruction (reconstruct.comp's TEMPORAL; ReconstructInputs::pipe is that variant): the temporal
// accumulation's last frame (`history`) and this frame's (`accumulated`, written). Its validity and blend weight are the
// camera block's (CloudParams::misc).
struct ReconstructTemporal {
  cumulo::render::TextureHandle history, accumulated;
};

// Adds `name`: writes `color` (this frame's reconstruction, the next frame's history) and `depth`; with `merged`
// (and ReconstructInputs::near_color, near_depth), `color` and `merged` (near over far) instead of `depth`; with
// `temporal`, the accumulation of its result as well.
void add_reconstruct_pass(cumulo::render::RenderGraph& graph, gpu::Context& ctx, const char* name, const ReconstructInputs& in,
                          cumulo::render::TextureHandle& color, cumulo::render::TextureHandle& depth,
                          ReconstructMerged* merged = nullptr, ReconstructTemporal* temporal = nullptr);

}  // namespace cumulo::clouds::render
