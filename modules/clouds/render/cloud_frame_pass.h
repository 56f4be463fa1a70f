#pragma once
// The passes drawn over the frame after the clouds' own (the lightning bolts and the rain, the light
// shafts, ...): each is a CloudFramePass in files of its own, registered by one line in
// cloud_frame_passes.cpp (or, from outside, CloudFeature::add_frame_pass), and called in that order with
// the frame, its cloud inputs and the march's outputs.
#include <memory>
#include <vector>

#include "engine/render/render_feature.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/render/cloud_render_options.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::clouds::render {

struct CloudFramePassContext {
  cumulo::render::StageContext& stage;  // the graph, the snapshot, the slot, the scene's hdr and depth
  const CloudFrame& frame;
  const CloudFrameInputs& in;     // this frame's cloud inputs (sun, ambient, haze, instances with assets)
  const CloudPassOutputs& clouds;  // the march's colour and depth
};

class CloudFramePass {
 public:
  virtual ~CloudFramePass() = default;
  // Creates the GPU objects when the options draw it (false: it is left out of the run). `options` outlives
  // the pass and may change between frames (cumulo fidelity sets reference_comparable).
  virtual bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options) = 0;
  virtual void destroy_gpu() = 0;
  // Adds the passes of this frame and returns the new hdr (`c.stage.hdr` when it draws nothing).
  virtual cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) = 0;
};

// The registered passes, in drawing order (cloud_frame_passes.cpp).
std::vector<std::unique_ptr<CloudFramePass>> make_cloud_frame_passes();

}  // namespace cumulo::clouds::render
