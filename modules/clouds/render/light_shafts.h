#pragma once
// Light shafts through gaps in the clouds (issue 10; 2017 talk, seed 001 "Post Processing": a radial
// blur of the unoccluded sun, used as the mask of the atmosphere's Mie in-scattering).
//
//   clouds.light_shafts        compute  quarter resolution: the shaft intensity (shaders/clouds/light_shafts.comp)
//   clouds.light_shafts_apply  compute  full resolution: hdr minus the Mie in-scattering the shafts' shadow
//                                       takes out (light_shafts_apply.comp)
//
// Skipped when the highlight around the sun is outside the view, the sun below the horizon, or there is
// no haze to scatter in.
#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/render/graph/render_graph.h"
#include "engine/scene/camera.h"
#include "modules/clouds/render/cloud_renderer.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

struct LightShaftInputs {
  scene::CameraView camera;
  uint32_t slot = 0;
  glm::vec3 sun_direction{0.0f, 1.0f, 0.0f};  // toward the sun
  glm::vec3 sun_color{1.0f};                  // illuminance (pi x the engine's Lambertian radiance)
  float haze_density = 0.0f, haze_falloff = 0.001f;  // the scene's height haze (SceneLighting fog_*)
  // Constants (2017 talk: the mask scales the atmosphere's Mie term; Mitchell's decay per sample).
  float mie_g = 0.76f;          // the Mie lobe's eccentricity (Hillaire's Earth preset)
  float strength = 1.0f;  // x the haze model's in-scattering, as Mie
  float highlight_degrees = 12.0f;  // angular radius of the highlight around the sun
  uint32_t samples = 32;
  float resolution_scale = 0.25f;  // of the output, per axis: the blurred mask is smooth
  float decay = 0.97f;
  float blur_length = 0.85f;    // fraction of the way to the sun the blur reaches
  float sky_distance_m = 30000.0f;
  float darkest = 0.4f;         // the shadowed part keeps at least this fraction of its colour
};

class LightShafts {
 public:
  LightShafts(gpu::Context& ctx, gpu::PipelineLibrary& library);
  // Adds the passes and returns the new `hdr` (or `hdr` when skipped). `sky_color`: the 2.5D sky's
  // colour (invalid: none).
  cumulo::render::TextureHandle add_passes(cumulo::render::RenderGraph& graph, const LightShaftInputs& in,
                                           cumulo::render::TextureHandle hdr, cumulo::render::TextureHandle depth,
                                           const CloudPassOutputs& clouds, cumulo::render::TextureHandle sky_color);
  // Whether this frame's inputs would draw shafts (the sun in front of the camera, above the horizon, haze).
  static bool active(const LightShaftInputs& in);

 private:
  gpu::Context& ctx_;
  gpu::Pipeline* shafts_ = nullptr;
  gpu::Pipeline* apply_ = nullptr;
  gpu::Buffer ubo_[gpu::kFramesInFlight];
  gpu::Image white_;  // 1x1: the 2.5D sky's transmittance when there is none
  VkSampler linear_ = VK_NULL_HANDLE, nearest_ = VK_NULL_HANDLE;
};

}  // namespace cumulo::clouds::render
