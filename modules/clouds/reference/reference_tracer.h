#pragma once
// The path-traced reference of the clouds (issue 11): a Monte Carlo path tracer on the Vulkan device of
// exactly the density field the real-time march samples (the same CloudParams block and up-rez sampler,
// shaders/clouds/reference_trace.comp), lit by the same sun, the atmosphere's sky and, for lightning, the
// same point lights; the terrain an opaque Lambertian heightfield (reference_scene.h). Progressive: every
// frame adds `samples_per_frame` samples per pixel to an accumulation on the GPU and the mean becomes the
// frame's scene colour, which the engine tonemaps as usual. Deterministic for a seed.
//
//   clouds.reference_majorant  compute  once per asset: a bound of the density per 8^3 modeling voxels
//   clouds.reference_trace     compute  samples -> accumulation (rgb sum, luminance^2 sum; view-ray
//                                       transmittance, sample count, majorant violations)
//   clouds.reference_resolve   compute  mean -> hdr (the whole picture: clouds, terrain, sky)
//   clouds.reference_readback  copy     accumulation -> host (read())
//
//   ReferenceTracer tracer(ctx, library);
//   tracer.settings().max_bounces = 64;
//   feature.set_reference(&tracer);        // CloudFeature calls add_passes in place of the cloud passes
//   ... frames ...; ReferenceImage img = tracer.read();   // once a frame completed
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "engine/core/enum_names.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/graph/render_graph.h"
#include "modules/clouds/render/cloud_feature.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/reference/reference_scene.h"

namespace cumulo::gpu {
class Context;
class Pipeline;
class PipelineLibrary;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

enum class ReferencePhase : uint8_t {
  Cloud,      // the real-time march's dual-lobe HG (CloudSettings hg_*), so the comparison isolates the lighting model
  Mie,        // Jendersie & d'Eon 2023's approximate Mie phase for water droplets (HG + Draine)
  Isotropic,  // tests
};
inline constexpr std::array kReferencePhaseNames{EnumName<ReferencePhase>{ReferencePhase::Cloud, "cloud"},
                                                 EnumName<ReferencePhase>{ReferencePhase::Mie, "mie"},
                                                 EnumName<ReferencePhase>{ReferencePhase::Isotropic, "isotropic"}};
inline const char* reference_phase_name(ReferencePhase p) { return name_of(kReferencePhaseNames, p); }

// Jendersie & d'Eon 2023 ("An Approximate Mie Scattering Function for Fog and Cloud Rendering"), their fit
// for droplet diameters 5..50 um: g_HG, g_D, alpha and the Draine weight.
struct MiePhase {
  float g_hg = 0.0f, g_draine = 0.0f, alpha = 0.0f, w_draine = 0.0f;
  static MiePhase for_droplet(float diameter_um);
};

// A homogeneous box in place of the cloudscape (tests: analytic solutions).
struct AnalyticMedium {
  glm::vec3 min{0.0f}, max{0.0f};
  float extinction = 0.0f;  // 1/m
  float albedo = 1.0f;
  float majorant = 0.0f;    // 1/m (>= extinction; larger exercises the null collisions); 0: the extinction
};

struct ReferenceSettings {
  uint32_t max_bounces = 64;  // scattering events per path (1: single scattering)
  ReferencePhase phase = ReferencePhase::Cloud;
  float droplet_um = 20.0f;   // ReferencePhase::Mie
  uint32_t seed = 1;
  uint32_t samples_per_frame = 1;
  bool sun = true, sky = true, terrain = true, aerial = true, lights = true;
  float uniform_sky = -1.0f;  // >= 0: the sky is this grey radiance in every direction (tests); < 0: the environment
  bool uniform_sky_upper_only = false;  // the uniform sky above the horizon only (black below: a dark ground, for tests)
  // Point-light intensity per unit CloudPointLight colour: the terrain's lightning light (cloud_feature.cpp)
  // is 0.0015 x the flash's intensity as the radiance of a white Lambertian facing it at 500 m, i.e. an
  // intensity of pi x 500^2 x 0.0015 per unit: the same flash, physically.
  float light_scale = 3.14159265f * 250000.0f * 0.0015f;
  std::optional<AnalyticMedium> analytic;
};

// The accumulation's mean (read back after a completed frame). Row-major, top row first.
struct ReferenceImage {
  uint32_t width = 0, height = 0;
  uint32_t samples = 0;              // per pixel
  std::vector<glm::vec4> radiance;   // rgb mean radiance; a: cloud opacity of the view ray (1 - mean transmittance)
  std::vector<float> luminance_stderr;  // standard error of the mean luminance
  double majorant_violations = 0.0;  // densities found above the majorant (0: the bound held)
};

class ReferenceTracer final : public CloudFrameOverride {
 public:
  ReferenceTracer(gpu::Context& ctx, gpu::PipelineLibrary& library);
  ~ReferenceTracer();
  ReferenceTracer(const ReferenceTracer&) = delete;
  ReferenceTracer& operator=(const ReferenceTracer&) = delete;

  ReferenceSettings& settings() { return settings_; }
  // The next frame starts a new accumulation (also after a change of size; the caller resets after a
  // change of view, sun or settings).
  void reset() { samples_ = 0; }
  uint32_t samples() const { return samples_; }  // per pixel, including the frames recorded so far

  // The terrain, ocean and sky: add_passes(snapshot, ...) sets them from the snapshot when its models, sun,
  // camera altitude or haze changed; tests set them directly.
  void set_terrain(const TerrainHeightfield& terrain);
  void set_sky(const SkyEnvironment& sky);
  void set_ocean(std::optional<glm::vec4> height_and_albedo) { ocean_ = height_and_albedo; }

  // Adds the passes (trace, resolve, readback; the majorants once per asset) and returns the new `hdr`.
  cumulo::render::TextureHandle add_passes(cumulo::render::RenderGraph& graph, const cumulo::render::FrameSnapshot& snapshot,
                                           const CloudFrameInputs& in, const CloudLightOutputs& light,
                                           cumulo::render::TextureHandle hdr, cumulo::render::TextureHandle depth) override;
  cumulo::render::TextureHandle add_passes(cumulo::render::RenderGraph& graph, const CloudFrameInputs& in,
                                           const CloudLightOutputs& light, cumulo::render::TextureHandle hdr,
                                           cumulo::render::TextureHandle depth);
  // The accumulation as of the last completed frame.
  ReferenceImage read() const;

 private:
  struct Majorant {
    gpu::Image image;
    cumulo::render::PersistentTexture texture;
    uint64_t revision = ~0ull;  // the asset's revision it was built from (~0: never)
  };
  gpu::Pipeline& trace_pipeline(bool analytic, int asset_slots, bool coverage_texture = false, bool envelope = false);
  void prepare_scene(const cumulo::render::FrameSnapshot& snapshot);

  gpu::Context& ctx_;
  gpu::PipelineLibrary& library_;
  ReferenceSettings settings_;
  std::map<std::tuple<bool, int, bool, bool>, gpu::Pipeline*> trace_pipes_;
  gpu::Pipeline* majorant_pipe_ = nullptr;
  gpu::Pipeline* resolve_pipe_ = nullptr;
  gpu::Buffer cloud_ubo_[gpu::kFramesInFlight], ref_ubo_[gpu::kFramesInFlight];
  std::map<const CloudAsset*, Majorant> majorants_;
  gpu::Image accum_image_, aux_image_;
  cumulo::render::PersistentTexture accum_, aux_;
  gpu::Buffer accum_readback_, aux_readback_;
  uint32_t samples_ = 0;
  uint32_t read_samples_ = 0;
  // The scene beyond the clouds.
  TerrainHeightfield terrain_cpu_;
  gpu::Image terrain_, sky_, no_terrain_, no_sky_, no_aerial_;
  gpu::Image no_volume_;  // a frame without voxel instances (the envelope alone): the modeling, noise and majorant
  std::optional<glm::vec4> ocean_;  // xyz: albedo, w: height
  const void* scene_models_ = nullptr;
  size_t scene_model_count_ = 0;
  glm::vec4 sky_key_{0.0f};
  VkSampler linear_clamp_ = VK_NULL_HANDLE, linear_repeat_ = VK_NULL_HANDLE, nearest_clamp_ = VK_NULL_HANDLE;
};

}  // namespace cumulo::clouds::render
