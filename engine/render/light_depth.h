#pragma once
// The scene's geometry seen from the key light (the sun, or the moon at night): an orthographic depth
// map over the bounds of every model, so a module can tell whether the terrain hides the light from a
// point (issue 10: "the sun behind a mountain darkens the cloud base near it"). Re-rendered only when
// the light turns (more than kLightDepthRebuildDegrees) or the models change; otherwise the persistent
// texture of the last render is imported as it is.
//
//   render::LightDepth d = light_depth_.add_pass(graph, snapshot);   // before Stage::BeforeScene
//   if (d.texture.valid()) ... d.world_to_light * vec4(p, 1): xy in [-1, 1] (uv = xy * 0.5 + 0.5), z the
//                               depth in [0, 1] (0 at the light's side); texel z < point z: in shadow
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "engine/gpu/image.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/graph/render_graph.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::render {

class GpuSceneCache;

// What a frame's passes get (StageContext::light_depth).
struct LightDepth {
  TextureHandle texture;           // D32F; invalid: no map this frame (no models, the light below the horizon)
  glm::mat4 world_to_light{1.0f};  // world -> the map's NDC (xy -1..1, z 0..1 toward the light's far side)
  float depth_range_m = 1.0f;      // metres of world along the light per unit of depth
};

inline constexpr float kLightDepthRebuildDegrees = 0.1f;

class LightDepthMap {
 public:
  LightDepthMap(gpu::Context& ctx, gpu::PipelineLibrary& library, GpuSceneCache& scene, uint32_t size);
  ~LightDepthMap();
  LightDepth add_pass(RenderGraph& graph, const FrameSnapshot& snapshot);
  uint32_t renders() const { return renders_; }  // how many times the map was drawn (tests)

 private:
  gpu::Context& ctx_;
  GpuSceneCache& scene_;
  gpu::Pipeline* pipe_ = nullptr;
  uint32_t size_;
  gpu::Image image_;
  PersistentTexture texture_;
  uint64_t key_ = 0;  // the models and transforms of the last render
  glm::vec3 light_{0.0f};
  LightDepth last_;
  bool valid_ = false;
  uint32_t renders_ = 0;
};

}  // namespace cumulo::render
