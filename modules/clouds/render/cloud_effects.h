#pragma once
// The weather's effects drawn over the scene after the clouds (issue 9): the visible channel of ground
// lightning discharges (shaders/clouds/lightning_bolt.comp) and localized rain under precipitating clouds
// (shaders/clouds/rain.comp). Both are compute passes that read the scene depth and the cloud passes'
// colour and depth (so a cloud in front hides them) and add into the HDR scene colour.
//
//   clouds.lightning_bolt  compute  over the bolts' screen rectangle: channel core + air glow
//   clouds.rain            compute  over the rain columns' screen rectangle: a thin streaked medium
//
// Without bolts or rain columns nothing is added (the frame is bit-identical).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/gpu/frames.h"
#include "engine/render/graph/render_graph.h"
#include "engine/scene/camera.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

// A column of rain under a cloud: from `base_center` (the cloud base) down to `bottom` (world y).
struct RainColumn {
  glm::vec3 base_center{0.0f};
  float radius = 300.0f;
  float bottom = 0.0f;
  float intensity = 0.0f;  // 0..1, already faded by the cloud's dissipation
};

struct CloudEffectsInputs {
  scene::CameraView camera;
  double time = 0.0;
  uint32_t slot = 0;
  std::vector<BoltFrame> bolts;  // at most 2 drawn (the brightest)
  std::vector<RainColumn> rain;  // at most CLOUD_MAX_RAIN
  glm::vec3 bolt_color{0.75f, 0.8f, 1.0f};
  glm::vec3 rain_light{0.3f};  // what the drops scatter: the sky ambient and some sun
};

class CloudEffects {
 public:
  CloudEffects(gpu::Context& ctx, gpu::PipelineLibrary& library);
  // Adds the passes this frame needs and returns the new `hdr`. `clouds` may be empty (no cloud passes).
  cumulo::render::TextureHandle add_passes(cumulo::render::RenderGraph& graph, const CloudEffectsInputs& in,
                                           cumulo::render::TextureHandle hdr, cumulo::render::TextureHandle depth,
                                           const CloudPassOutputs& clouds);

 private:
  gpu::Context& ctx_;
  gpu::Pipeline* bolt_ = nullptr;
  gpu::Pipeline* rain_ = nullptr;
  gpu::Buffer ubo_[gpu::kFramesInFlight];
  VkSampler nearest_ = VK_NULL_HANDLE;
};

}  // namespace cumulo::clouds::render
