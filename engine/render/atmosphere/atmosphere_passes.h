#pragma once
// The atmosphere's LUTs as render-graph passes (issue 10; Hillaire 2020), persistent textures of the
// graph, each recomputed only when what it depends on changes:
//   atmosphere.transmittance  compute 256x64   (r, mu) -> transmittance             the preset changes
//   atmosphere.multiscatter   compute 32x32    (r, mu_s) -> psi_ms                   the preset changes
//   atmosphere.sky_view       compute 192x108  (azimuth, elevation) -> sky radiance  the sun, the moon or the
//                                                                                     camera's altitude moves
//   atmosphere.aerial_perspective  compute 32x32x32 froxels -> in-scattering, transmittance   every frame
// The sky pass samples the sky-view LUT (and the transmittance for the sun's disc). The CPU model
// (atmosphere.h) computes the same integrals and is their reference in the tests.
#include <cstdint>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/render/atmosphere/atmosphere.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/graph/render_graph.h"
#include "shaders/shared/atmosphere_params.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::render {

struct AtmosphereLuts {
  TextureHandle transmittance, sky_view;
  VkBuffer ubo = VK_NULL_HANDLE;  // AtmosphereGpuParams of this frame
  TextureHandle aerial;  // 3D: the camera's aerial-perspective froxels (atmosphere_params.h ATMOSPHERE_AERIAL_*)
};

class AtmospherePasses {
 public:
  AtmospherePasses(gpu::Context& ctx, gpu::PipelineLibrary& library, const Atmosphere& atmosphere);
  AtmosphereLuts add_passes(RenderGraph& graph, const FrameSnapshot& s, uint32_t slot);
  // The GPU block for a snapshot (tests compare the LUTs with the CPU model through it).
  shared::AtmosphereGpuParams gpu_params(const FrameSnapshot& s) const;
  uint32_t sky_view_updates() const { return sky_view_updates_; }
  uint32_t lut_builds() const { return lut_builds_; }  // transmittance + multiple-scattering builds
  // SceneLighting::mie_scale in steps of 5 % (a weather blend rebuilds the LUTs at most every step).
  static float mie_scale_key(const FrameSnapshot& s);
  const gpu::Image& sky_view_image() const { return sky_view_; }

 private:
  gpu::Context& ctx_;
  const Atmosphere& atmosphere_;
  gpu::Pipeline* transmittance_pipe_ = nullptr;
  gpu::Pipeline* ms_pipe_ = nullptr;
  gpu::Pipeline* sky_view_pipe_ = nullptr;
  gpu::Pipeline* aerial_pipe_ = nullptr;
  gpu::Image transmittance_, ms_, sky_view_;
  PersistentTexture transmittance_tex_, ms_tex_, sky_view_tex_;
  gpu::Buffer ubo_[gpu::kFramesInFlight];
  bool luts_built_ = false;
  float built_mie_ = 0.0f;  // the Mie scattering the transmittance and psi_ms LUTs were built with
  uint32_t lut_builds_ = 0;
  bool have_key_ = false;
  glm::vec4 sky_key_{0.0f};  // sun direction and altitude of the sky-view LUT's last update
  float moon_key_ = 0.0f;
  uint32_t sky_view_updates_ = 0;
  VkSampler linear_ = VK_NULL_HANDLE;
};

}  // namespace cumulo::render
