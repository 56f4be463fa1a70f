#pragma once
// The passes of the clouds' frame besides the voxel clouds' own (the 2.5D sky, the lightning bolts and the
// rain, the light shafts, ...): each is a CloudFramePass in files of its own, registered by one line in
// cloud_frame_passes.cpp (or, from outside, CloudFeature::add_frame_pass), and called in that order: before
// the clouds' march with the inputs it may add to (the 2.5D sky's colour and depth, which the composite
// orders against the voxel clouds), and after it with the march's outputs.
#include <memory>
#include <vector>

#include "engine/render/render_feature.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/render/cloud_render_options.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::clouds::render {

// What the loaded level says about the passes it needs.
struct CloudLevelFacts {
  bool has_weather_scheduler = false;  // --cloud-sky auto draws the 2.5D sky then
  bool has_orographic_clouds = false;  // --envelope auto draws the Envelope method's clouds then
};

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
  virtual bool create_gpu(cumulo::render::GpuServices& g, const CloudRenderOptions& options,
                          const CloudLevelFacts& level) = 0;
  virtual void destroy_gpu() = 0;
  // Before the scene, after the voxel clouds' light passes: what this pass adds to the key light's shadow on the scene
  // (`shadow`: the voxel clouds' map, or none; the geometry reads the one map it becomes).
  virtual void add_before_scene(cumulo::render::StageContext& /*stage*/, const CloudFrame& /*frame*/,
                                const CloudFrameInputs& /*in*/, cumulo::render::LightShadowMap& /*shadow*/) {}
  // In place of the real-time passes when the path tracer draws the frame (reference_tracer.h): what it traces of this
  // pass, into `in`.
  virtual void add_before_reference(cumulo::render::StageContext& /*stage*/, const CloudFrame& /*frame*/,
                                    CloudFrameInputs& /*in*/) {}
  // Before the clouds' march: what the march and the composite take from this pass, into `in`.
  virtual void add_before_clouds(cumulo::render::StageContext& /*stage*/, const CloudFrame& /*frame*/,
                                 CloudFrameInputs& /*in*/) {}
  // After the clouds' march, before their composite: what the composite takes from this pass (the 2.5D sky's colour
  // and depth, which leave out what `voxel`, the march's colour and depth, hides), into `in`.
  virtual void add_before_composite(cumulo::render::StageContext& /*stage*/, const CloudFrame& /*frame*/,
                                    const CloudPassOutputs& /*voxel*/, CloudFrameInputs& /*in*/) {}
  // Adds the passes of this frame and returns the new hdr (`c.stage.hdr` when it draws nothing).
  virtual cumulo::render::TextureHandle add_passes(const CloudFramePassContext& c) = 0;
};

// The registered passes, in drawing order (cloud_frame_passes.cpp).
std::vector<std::unique_ptr<CloudFramePass>> make_cloud_frame_passes();

}  // namespace cumulo::clouds::render
