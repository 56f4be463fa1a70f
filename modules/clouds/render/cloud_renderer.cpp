#include "modules/clouds/render/cloud_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "engine/render/history.h"
#include "engine/render/sky_model.h"
#include "modules/clouds/render/pass_bindings.h"
#include "modules/clouds/render/reconstruct_pass.h"
#include "modules/clouds/scene/density_query.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::render {

using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::ResourceState;
using cumulo::render::TextureDesc;
using cumulo::render::Usage;

static_assert(kMaxInstances == CLOUD_MAX_INSTANCES && kMaxPointLights == CLOUD_MAX_POINT_LIGHTS && kMaxAssets == CLOUD_MAX_ASSETS);

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // rgb radiance, a transmittance
constexpr VkFormat kDepthFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // opacity-0.5 distance, steps, segment end
constexpr VkFormat kGridFormat = VK_FORMAT_R16G16B16A16_SFLOAT;   // summed density toward the sun, the sky, the sun in the own cloud, away from the sun in it

// The state an imported image is in when the graph starts and the next user finds it: sampled by
// compute or fragment shaders.
ResourceState sampled_state() { return ResourceState::shader_read_only(); }
}  // namespace

struct CloudResources {
  // One instance's slab of the light-grid image.
  struct LightGrid {
    bool valid = false;   // has been fully built
    glm::vec3 sun{0.0f};  // sun direction (asset space) of the last full rebuild
    uint64_t key = 0;     // what the grid depends on besides the sun (asset, transform, density)
    glm::vec3 last_sun{0.0f};       // sun direction of the last frame (asset space)
    uint32_t frames_same_sun = 0;   // frames since the sun last moved (the sweep is current after a cycle)
  };
  // ablation, segment, bc1 SDF, distance noise mip, mean-noise light samples, asset slots, terrain shadow,
  // coverage texture (the BC1 modeling NVDF)
  using MarchKey = std::tuple<int, int, bool, bool, bool, int, bool, bool>;

  gpu::Context& ctx;
  gpu::PipelineLibrary& library;
  std::shared_ptr<const CloudNoise> noise;
  CloudResourcesDesc desc;
  gpu::Buffer ubo[gpu::kFramesInFlight];
  // The light grids of all instances stacked along z (instance i in layers [i * gz, (i + 1) * gz)),
  // a persistent graph texture (the graph carries its state from frame to frame).
  gpu::Image grid_image;
  cumulo::render::PersistentTexture grid_texture;
  uint32_t grid_instances = 0;
  LightGrid grids[kMaxInstances];
  // Temporal accumulation: the graph's history pair (engine/render/history.h).
  cumulo::render::GpuHistory history{"clouds.history", kColorFormat, 1.0f,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  bool history_on = false;  // the last frame accumulated (a frame without temporal breaks the history)
  // Reprojection of the sub-sampled march: the last frame's reconstruction.
  cumulo::render::GpuHistory recon_history{"clouds.reprojection", kColorFormat, 1.0f,
                                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  uint32_t recon_block = 0;  // block size of the last frame's reconstruction (0: none)
  gpu::Pipeline* recon_pipe = nullptr;
  glm::mat4 prev_view_proj{1.0f};
  gpu::Pipeline* grid_pipe = nullptr;
  gpu::Pipeline* temporal_pipe = nullptr;
  gpu::Pipeline* merge_pipe = nullptr;
  gpu::Pipeline* composite_pipes[2][2] = {};  // [with the 2.5D sky (SKY_LAYER)][with the aerial froxels (AERIAL)]
  gpu::Pipeline* shadow_pipe = nullptr;
  // The clouds' shadow map (persistent; recomputed when the grid or the plane changes).
  gpu::Image shadow_image;
  cumulo::render::PersistentTexture shadow_texture;
  glm::vec4 shadow_key{0.0f};
  glm::vec3 shadow_sun{0.0f};
  bool shadow_valid = false;
  uint32_t shadow_updates = 0;
  std::map<MarchKey, gpu::Pipeline*> march_pipes;
  uint32_t rebuilds = 0;
  VkSampler linear_clamp = VK_NULL_HANDLE, linear_repeat = VK_NULL_HANDLE, nearest_clamp = VK_NULL_HANDLE;

  CloudResources(gpu::Context& c, gpu::PipelineLibrary& lib) : ctx(c), library(lib) {}

  gpu::Pipeline& march(CloudAblation a, int segment, bool bc1, bool distance_mip, bool mean_light_noise,
                       int asset_slots = 1, bool terrain_shadow = false, bool coverage_texture = false) {
    MarchKey key{int(a), segment, bc1, distance_mip, mean_light_noise, asset_slots, terrain_shadow, coverage_texture};
    auto it = march_pipes.find(key);
    if (it != march_pipes.end()) return *it->second;
    static const char* kSegments[] = {"all", "near", "far"};
    gpu::ComputePipelineDesc d;
    d.shader = "clouds/march_render.comp";
    d.defines = {{"ABLATION", std::to_string(int(a))},
                 {"SEGMENT", std::to_string(segment)},
                 {"SDF_BC1", bc1 ? "1" : "0"},
                 {"NOISE_MIP_DISTANCE", distance_mip ? "1" : "0"},
                 {"LIGHT_SAMPLE_NOISE_MEAN", mean_light_noise ? "1" : "0"},
                 {"CLOUD_ASSET_SLOTS", std::to_string(asset_slots)},
                 {"TERRAIN_SHADOW", terrain_shadow ? "1" : "0"},
                 {"COVERAGE_TEXTURE", coverage_texture ? "1" : "0"}};
    d.name = std::string("clouds.march (") + ablation_name(a) + ", " + kSegments[segment] + (bc1 ? ", bc1 sdf" : "") +
             (distance_mip ? "" : ", mip 0") + (mean_light_noise ? "" : ", sampled light noise") +
             (asset_slots > 1 ? ", 2 assets" : "") + (terrain_shadow ? ", terrain shadow" : "") +
             (coverage_texture ? ", coverage texture" : "") + ")";
    gpu::Pipeline& p = library.compute(d);
    march_pipes[key] = &p;
    return p;
  }
  gpu::Pipeline& sweep(bool bc1, bool coverage_texture = false) {
    MarchKey key{-2, 0, bc1, true, true, 1, false, coverage_texture};
    auto it = march_pipes.find(key);
    if (it != march_pipes.end()) return *it->second;
    gpu::Pipeline& p = library.compute({.shader = "clouds/light_grid_sweep.comp",
                                        .defines = {{"SDF_BC1", bc1 ? "1" : "0"}, {"COVERAGE_TEXTURE", coverage_texture ? "1" : "0"}},
                                        .name = std::string("clouds.light_grid (sweep") + (bc1 ? ", bc1 sdf" : "") +
                                                (coverage_texture ? ", coverage texture" : "") + ")"});
    march_pipes[key] = &p;
    return p;
  }
  gpu::Pipeline& grid(bool bc1, bool coverage_texture = false) {
    // The grid shader samples the SDF too: built per SDF form.
    MarchKey key{-1, 0, bc1, true, true, 1, false, coverage_texture};
    auto it = march_pipes.find(key);
    if (it != march_pipes.end()) return *it->second;
    gpu::Pipeline& p = library.compute({.shader = "clouds/light_grid_update.comp",
                                        .defines = {{"SDF_BC1", bc1 ? "1" : "0"}, {"COVERAGE_TEXTURE", coverage_texture ? "1" : "0"}},
                                        .name = bc1 || coverage_texture
                                                    ? std::string("clouds.light_grid (") +
                                                          (bc1 && coverage_texture ? "bc1 sdf, coverage texture"
                                                           : bc1                   ? "bc1 sdf"
                                                                                   : "coverage texture") + ")"
                                                    : std::string("clouds.light_grid")});
    march_pipes[key] = &p;
    return p;
  }
};

void CloudResourcesDeleter::operator()(CloudResources* r) const {
  if (!r) return;
  r->ctx.wait_idle();  // frames in flight may still read the light grids and history
  delete r;
}

namespace {

using Bindings = PassBindings;

shared::CloudMarchPush target_push(VkExtent3D e) {
  shared::CloudMarchPush pc{};
  pc.target = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
  pc.sub = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
  return pc;
}

glm::mat4 instance_matrix(const CloudInstance& inst) { return placement_matrix(inst); }

uint64_t instance_key(const CloudInstance& inst, const CloudResourcesDesc& d) {
  struct Key {
    const void* asset;
    float v[12];
    uint32_t grid[3];
  } k{};
  k.asset = inst.asset.get();
  const glm::quat q = glm::normalize(inst.rotation);
  const float vals[12] = {inst.position.x, inst.position.y, inst.position.z, q.x, q.y, q.z, q.w,
                          inst.scale, inst.density, inst.dissipation, inst.coverage, 0.0f};
  std::memcpy(k.v, vals, sizeof vals);
  k.grid[0] = d.light_grid_size.x, k.grid[1] = d.light_grid_size.y, k.grid[2] = d.light_grid_size.z;
  return hash64(&k, sizeof k);
}

}  // namespace

shared::CloudInstanceParams cloud_instance_params(const CloudInstance& inst, glm::vec3 sun, double time) {
  shared::CloudInstanceParams ip{};
  ip.world_to_asset = glm::inverse(instance_matrix(inst));
  const float scale = std::max(inst.scale, 1e-6f);
  ip.bounds_min = glm::vec4(inst.asset->bounds_min, scale);
  ip.bounds_max = glm::vec4(inst.asset->bounds_max, 1.0f / scale);
  const glm::quat inv_rot = glm::inverse(glm::normalize(inst.rotation));
  ip.sun_dir = glm::vec4(glm::normalize(inv_rot * glm::normalize(sun)), inst.density);
  ip.sky_dir = glm::vec4(glm::normalize(inv_rot * glm::vec3(0.0f, 1.0f, 0.0f)), std::clamp(inst.dissipation, 0.0f, 1.0f));
  ip.wind_offset = glm::vec4(wind_offset_asset(inst, time), 0.0f);  // asset metres
  const float coverage = std::clamp(inst.coverage, 0.0f, 1.0f);
  // At this coverage every cloud at or above the band is absent: the fair-weather field is the whole story.
  const bool fair = inst.asset->has_field_fair && coverage <= float(CLOUD_COVERAGE_BAND - CLOUD_COVERAGE_RAMP) + 1e-6f;
  ip.weather = glm::vec4(coverage, fair ? 1.0f : 0.0f, 0.0f, 0.0f);
  return ip;
}

namespace {

shared::CloudParams make_params_impl(const CloudFrameInputs& in, VkExtent2D size, bool history_valid,
                                     const std::vector<uint32_t>& slots) {
  const CloudSettings& s = in.settings;
  shared::CloudParams p{};
  p.view_proj = in.camera.view_proj;
  p.inv_view_proj = in.camera.inv_view_proj;
  p.camera_pos = glm::vec4(in.camera.position, float(in.time));
  const glm::vec3 sun = glm::normalize(in.sun_direction);
  p.sun_dir = glm::vec4(sun, s.ms_diffusion ? s.ms_enclosed_sky_depth : 0.0f);
  p.sun_color = glm::vec4(in.sun_color, s.ms_slab ? s.ms_lateral : 0.0f);
  p.ambient_color = glm::vec4(in.ambient_color, s.ms_slab ? s.ground_albedo : 0.0f);
  p.viewport = glm::vec4(float(size.width), float(size.height), 1.0f / float(size.width), 1.0f / float(size.height));
  const bool uniform_steps = s.ablation != CloudAblation::Full;
  p.march = glm::vec4(s.extinction, s.albedo, s.transmittance_limit, float(uniform_steps ? s.base_max_steps : s.max_steps));
  p.steps = glm::vec4(s.split_distance_m, s.animated_jitter_distance_m, s.base_step_m, s.noise_mip_distance_scale);
  p.phase = glm::vec4(s.hg_forward, s.hg_backward, s.hg_forward_weight, s.ms_strength);
  p.light = glm::vec4(s.light_sample_m, s.ambient_occlusion_scale, s.base_light_march_m, float(std::max(1u, s.base_light_samples)));
  p.misc = glm::vec4(s.jitter_scale, s.temporal_blend, s.light_grid_debug_height, history_valid ? 1.0f : 0.0f);
  p.frame = glm::uvec4(uint32_t(in.frame_index), uint32_t(in.instances.size()), uint32_t(in.lights.size()),
                       uint32_t(s.debug));
  const bool terrain = in.settings.terrain_shadow && in.terrain_depth.valid();
  p.haze = glm::vec4(in.haze_density, in.haze_falloff, terrain ? 1.0f : 0.0f, in.terrain_depth_range_m);
  p.light_depth = in.terrain_depth_matrix;
  p.effects = glm::uvec4(s.effects, s.instance_shadows ? 1u : 0u, 0u, 0u);
  p.ms = glm::vec4(s.ms_attenuation_inside, s.ms_attenuation, s.ms_diffusion ? (s.ms_slab ? 2.0f : 1.0f) : 0.0f, s.ms_other_cloud_attenuation);
  p.sky_zenith = glm::vec4(in.sky_zenith, s.ms_slab ? s.ms_anisotropy : 0.0f);
  p.sky_horizon = glm::vec4(in.sky_horizon, s.ms_slab ? s.edge_depth_scale : 0.0f);
  for (size_t i = 0; i < in.lights.size(); ++i) {
    p.light_pos[i] = glm::vec4(in.lights[i].position, std::max(in.lights[i].radius, 1e-3f));
    p.light_color[i] = glm::vec4(in.lights[i].color, 0.0f);
  }
  for (size_t i = 0; i < in.instances.size(); ++i) {
    p.instances[i] = cloud_instance_params(in.instances[i], sun, in.time);
    p.instances[i].wind_offset.w = float(slots[i]);
  }
  return p;
}

shared::CloudParams make_params(const CloudResources& res, const CloudFrameInputs& in, VkExtent2D size,
                                bool history_valid, const std::vector<uint32_t>& slots) {
  shared::CloudParams p = make_params_impl(in, size, history_valid, slots);
  p.prev_view_proj = res.prev_view_proj;
  return p;
}

}  // namespace

shared::CloudParams cloud_params(const CloudFrameInputs& in, VkExtent2D size, const std::vector<uint32_t>& slots) {
  std::vector<uint32_t> all = slots;
  all.resize(in.instances.size(), 0u);
  shared::CloudParams p = make_params_impl(in, size, false, all);
  p.prev_view_proj = in.camera.view_proj;
  return p;
}

namespace {

// Temporal history: the graph's ping-pong pair (last frame's result as `prev`, this frame's target as
// `next`). Invalid on the first frame, after a resize, a camera cut or a frame without accumulation.
struct HistoryImports {
  TextureHandle prev, next;
  bool valid = false;
};
HistoryImports import_history(CloudResources& res, RenderGraph& graph, bool camera_cut) {
  if (camera_cut || !res.history_on) res.history.invalidate();
  const cumulo::render::HistoryHandles h = res.history.import(res.ctx, graph);
  res.history_on = true;
  return {h.previous, h.current, h.valid};
}

}  // namespace

// The diffusion preset's multiple-scattering strength and ambient occlusion scale, calibrated with cumulo fidelity on
// three views of our own (not the acceptance set: a tower from the sunlit side, a mediocris from below against the
// sun, a humilis field at noon; 48 spp): strength 1 / 1.5 / 2 / 4 gave in-cloud bias -17..-36 % (talk constants) ...
// -3..-21 % (1.5, occlusion 0.05) ... +17 % / -11 % / +11 % (2) ... +30..+76 % (4).
constexpr float kDiffusionMsStrength = 1.5f;
// Other clouds' optical depth on the multiple scattering, by Beer-Lambert at this fraction of it: on the same
// views, 0 / 0.3 / 1 gave the tower +5.0 / +3.1 / +0.5 %, the mediocris -16.2 / -20.9 / -23.7 %, the humilis field
// +0.2 / -3.4 / -6.8 %, and the field under a low sun (where clouds shadow clouds) +35.1 / +22.1 / +14.9 %.
constexpr float kDiffusionOtherCloudAttenuation = 1.0f;
constexpr float kDiffusionAmbientOcclusion = 0.05f;
// The slab preset's, calibrated on the same four views of our own at 256 spp (docs/fidelity/diffusion_lighting.md):
// strength x forward lobe 1.25 / 1.5 / 1.75 / 2.0 x 0 / 0.5 / 1.0 gave a mean noise-corrected in-cloud error of
// 20.5 / 22.1 / 26.3, 19.0 / 18.6 / 23.3, 20.3 / 17.5 / 21.8, - / 18.5 / - % (diffusion 20.3 %).
// Then the dark edges from the optical depth to the nearest surface (edge depth scale, every pixel marched): edge x
// strength x lobe 0.5 / 1.75 / 0.5 30.8, 1 / 1.75 / 0.5 19.1, 2 / 1.75 / 0.5 16.4, 4 / 1.75 / 0.5 25.2, 2 / 1.5 / 0.5
// 15.5, 2.5 / 1.5 / 0.5 15.6, 3 / 1.25 / 0.5 15.5, 4 / 1.5 / 0.5 18.7, 2 / 1.5 / 0.25 14.8 % (the profile: 17.7 %).
// Then with two backlit views of our own added (the four were three with the sun behind the viewer, and the
// acceptance views with the sun behind the cloud came out 11-14 % dark), over the six (strength / lobe, edge 2):
// 1.5 / 0.25 15.5 % (biases to -18 %), 1.5 / 0.5 15.7, 1.75 / 0.5 15.8, 1.75 / 0.75 17.9, 1.6 / 0.35 15.1 (to -13),
// 1.65 / 0.4 15.2 (biases -11..+9), 1.7 / 0.4 15.3, 1.65 / 0.45 15.3; edge 1.5 / 2.5 / 3 at 1.65-1.75: 15.7 / 16.0 /
// 19.3. A leak of the fluence through the nearest surface (linear from the extrapolated boundary to a transport depth
// D) darkened every view: D 1 / 2 at strength 2 / 3 gave 17.0 / 16.4 %; not kept.
// The sky's hemisphere mean instead of 0.5 (zenith + horizon) (half as bright, neutral at a low sun; visibly closer
// to the reference's blue-grey shadows at dusk) measured on the seven views (a seventh, the tower at a low sun, added)
// 16.1 % at 1.65 / 0.4, 16.1 at 1.9 / 0.4, 18.1 at 2.15, 16.0 at 1.9 with the sky occlusion 0.5, 16.3 with the ground
// albedo 0.2, 17.5 at 1.9 / 0.6, 16.4 at 1.8 / 0.5, against 15.3 % with 0.5 (zenith + horizon): off by default,
// --cloud-sky-mean on. The seven with it off: 1.5 / 0.25 15.6 % (biases to -18 %), 1.6 / 0.35 15.2 (to -13), 1.65 /
// 0.4 15.3 (to -11): 1.65 / 0.4 kept (ties within 0.5 points go to the smaller worst bias).
constexpr bool kSlabSkyMeanAmbient = false;
// Then the lateral leak (march_render.comp) over the seven, lateral / strength (lobe 0.4): 1 / 1.65 15.7 %, 3 / 1.65
// 18.6, 1 / 1.85 15.4, 0.5 / 1.75 15.0 (biases -10..+7), 0.75 / 1.8 15.2 (-9..+6), 0.5 / 1.8 15.1 (-8..+9): 0.5 / 1.8
// kept by the same rule.
constexpr float kSlabMsLateral = 0.5f;
constexpr float kSlabMsStrength = 1.8f;
constexpr float kSlabMsAnisotropy = 0.4f;
constexpr float kSlabEdgeDepthScale = 2.0f;
constexpr float kSlabOtherCloudAttenuation = 1.0f;
// The sky's single scattering at the column's optical depth as it is: against a single-scattering reference
// (--max-bounces 1) the sky from the upper hemisphere at 1.0 gave ground / mixed / long shadows +7 / +2 / +15 %
// where the isotropic ambient at 0.05 gave +55 / +117 / +212 %.
constexpr float kSlabAmbientOcclusion = 1.0f;
// A chamber: the storm cloud's (roof ~100 m and more) has a sky optical depth of 5 and more; 0.5 / 1 / 3 / 10 gave
// the lair 20.6 / 20.7 / 20.9 / 26.5 % at 48 spp and the low-sun overview the same within 0.3 %.
constexpr float kSlabEnclosedSkyDepth = 3.0f;
// Mostly ocean below the sample's clouds: 0 / 0.05 / 0.1 moved the three cameras by 1-3 points.
constexpr float kSlabGroundAlbedo = 0.1f;

void apply_lighting_preset(CloudSettings& s, CloudLightingPreset p) {
  const CloudSettings talk;
  s.ms_strength = talk.ms_strength;
  s.ambient_occlusion_scale = talk.ambient_occlusion_scale;
  s.ms_attenuation_inside = talk.ms_attenuation_inside;
  s.ms_attenuation = talk.ms_attenuation;
  s.ms_diffusion = talk.ms_diffusion;
  s.ms_slab = talk.ms_slab;
  s.ms_enclosed_sky_depth = talk.ms_enclosed_sky_depth;
  s.ground_albedo = talk.ground_albedo;
  s.ms_anisotropy = talk.ms_anisotropy;
  s.edge_depth_scale = talk.edge_depth_scale;
  s.instance_shadows = talk.instance_shadows;
  s.sky_mean_ambient = talk.sky_mean_ambient;
  s.ms_lateral = talk.ms_lateral;
  s.ms_other_cloud_attenuation = talk.ms_other_cloud_attenuation;
  if (p == CloudLightingPreset::Slab) {
    s.ms_diffusion = s.ms_slab = true;
    s.ms_other_cloud_attenuation = kSlabOtherCloudAttenuation;
    s.ms_strength = kSlabMsStrength;
    s.ambient_occlusion_scale = kSlabAmbientOcclusion;
    s.ms_enclosed_sky_depth = kSlabEnclosedSkyDepth;
    s.ground_albedo = kSlabGroundAlbedo;
    s.ms_anisotropy = kSlabMsAnisotropy;
    s.edge_depth_scale = kSlabEdgeDepthScale;
    s.instance_shadows = true;
    s.sky_mean_ambient = kSlabSkyMeanAmbient;
    s.ms_lateral = kSlabMsLateral;
    return;
  }
  if (p == CloudLightingPreset::Diffusion) {
    s.ms_diffusion = true;
    s.ms_other_cloud_attenuation = kDiffusionOtherCloudAttenuation;
    s.ms_strength = kDiffusionMsStrength;
    s.ambient_occlusion_scale = kDiffusionAmbientOcclusion;
    return;
  }
  if (p != CloudLightingPreset::Tuned) return;
  // From cumulo fidelity on the sample level (docs/fidelity, 256 spp, --reuse-references sweeps): the talks'
  // constants leave sunlit clouds 14-39 % darker than the reference in cloud; 2.2x the multiple scattering and
  // 0.65x the ambient occlusion bring 7 of the 9 views closer (mixed 34 -> 20 %); more overshoots the views
  // that are already too bright (the sun behind the cloud, the low sun). The inner glow's relaxed attenuation
  // (ms_attenuation_inside) made no difference worth keeping (0.05..0.25: within 3 %).
  s.ms_strength = 2.2f;
  s.ambient_occlusion_scale = 0.065f;
}

uint32_t cloud_effect_bit(std::string_view name) {
  for (const CloudEffectName& e : kCloudEffects)
    if (name == e.name) return e.bit;
  return 0;
}
static_assert(int(CloudDebugView::Profile) == CLOUD_DEBUG_PROFILE && int(CloudDebugView::Steps) == CLOUD_DEBUG_STEPS &&
              int(CloudDebugView::LightGrid) == CLOUD_DEBUG_LIGHT_GRID && int(CloudDebugView::Split) == CLOUD_DEBUG_SPLIT);
static_assert(int(CloudAblation::Base) == CLOUD_ABLATION_BASE && int(CloudAblation::Full) == CLOUD_ABLATION_FULL);

CloudResourcesPtr create_cloud_resources(gpu::Context& ctx, gpu::PipelineLibrary& library,
                                         std::shared_ptr<const CloudNoise> noise, const CloudResourcesDesc& desc) {
  if (!ctx.info().push_descriptors)
    fail("%s: the cloud passes need VK_KHR_push_descriptor, which this device lacks", ctx.info().name.c_str());
  if (!noise) fail("clouds: create_cloud_resources needs the voxel noise (load it with CloudAssetCache::noise)");
  if (desc.light_grid_divisions == 0 || desc.light_grid_size.z % desc.light_grid_divisions != 0)
    fail("clouds: the light grid's %u z layers do not split into %u slabs", desc.light_grid_size.z,
         desc.light_grid_divisions);
  CloudResourcesPtr res(new CloudResources(ctx, library));
  res->noise = std::move(noise);
  res->desc = desc;
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    res->ubo[i] = gpu::Buffer(ctx, {sizeof(shared::CloudParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                                    i ? "clouds.params.1" : "clouds.params.0"});
  res->grid_pipe = &res->grid(false);
  res->temporal_pipe = &library.compute({.shader = "clouds/temporal_accumulate.comp", .name = "clouds.temporal"});
  res->recon_pipe = &library.compute({.shader = "clouds/reconstruct.comp", .name = "clouds.reconstruct"});
  res->merge_pipe = &library.compute({.shader = "clouds/split_merge.comp", .name = "clouds.split_merge"});
  for (int sky = 0; sky < 2; ++sky)
    for (int aerial = 0; aerial < 2; ++aerial)
      res->composite_pipes[sky][aerial] = &library.compute(
          {.shader = "clouds/composite_apply.comp",
           .defines = {{"SKY_LAYER", sky ? "1" : "0"}, {"AERIAL", aerial ? "1" : "0"}},
           .name = std::string("clouds.composite") + (sky ? " (2.5D sky)" : "") + (aerial ? " (aerial froxels)" : "")});
  res->shadow_pipe = &library.compute({.shader = "clouds/shadow_map.comp", .name = "clouds.shadow_map"});
  res->march(CloudAblation::Full, CLOUD_SEGMENT_ALL, false, true, true);  // the common variant, built up front
  res->linear_clamp = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  res->linear_repeat = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
  res->nearest_clamp = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
  return res;
}

CloudFrameInputs cloud_inputs_from_snapshot(const cumulo::render::FrameSnapshot& snap, uint32_t slot,
                                            const CloudSettings& settings) {
  CloudFrameInputs in;
  in.camera = snap.camera;
  in.frame_index = snap.frame_index;
  in.time = snap.sim_time;
  in.slot = slot;
  in.settings = settings;
  apply_budget_mode(in.settings, cumulo::render::budget_hz(snap.mode));
  in.sun_direction = cumulo::render::key_light_direction(snap);  // the sun, or the moon at night
  // The key light's irradiance at the ground: pi x the Lambertian radiance the geometry is lit with (the
  // atmosphere's sun, or the moon at night), so the clouds and the terrain see one sun. (Until issue 11 this
  // was pi x scene::SunLight::radiance, the stand-in model's unscaled radiance: a third of the terrain's sun,
  // which the path-traced reference showed.)
  in.sun_color = snap.lighting.sun_radiance * 3.14159265f;
  const bool mean_known = snap.lighting.sky_mean != glm::vec3(0.0f);
  in.ambient_color = (in.settings.sky_mean_ambient && mean_known ? snap.lighting.sky_mean
                                                                 : 0.5f * (snap.lighting.sky_zenith + snap.lighting.sky_horizon)) *
                     snap.lighting.ambient;
  in.haze_density = snap.lighting.fog_density;
  in.haze_falloff = snap.lighting.fog_falloff;
  in.sky_zenith = snap.lighting.sky_zenith;
  in.sky_horizon = snap.lighting.sky_horizon;
  return in;
}

CloudResourcesDesc CloudResourcesDesc::for_device(const gpu::DeviceInfo& device) {
  CloudResourcesDesc d;
  if (device.is_cpu()) {
    d.light_grid_size = {96, 16, 96};
    // One level of the sweep per frame: on lavapipe each dispatch has a fixed cost (~0.2 ms), and at
    // 20 fps 16 frames are 0.8 s (the sweep does not follow the wind; a moving sun lags that much).
    d.light_grid_divisions = 16;
    d.shadow_map_size = 128;  // 32 m texels over the sample box at noon: the CPU grid's 43 m voxels need no finer
  }
  return d;
}

uint64_t persistent_gpu_bytes(const CloudResources& res) {
  uint64_t total = 0;
  if (res.grid_image)
    total += uint64_t(res.grid_image.extent().width) * res.grid_image.extent().height * res.grid_image.extent().depth * 4;
  if (res.history.texture().has_images())
    total += 2ull * res.history.texture().desc().width * res.history.texture().desc().height * 8;
  if (res.recon_history.texture().has_images())
    total += 2ull * res.recon_history.texture().desc().width * res.recon_history.texture().desc().height * 8;
  if (res.shadow_image) total += uint64_t(res.shadow_image.extent().width) * res.shadow_image.extent().height * 2;
  return total;
}

uint32_t light_grid_rebuilds(const CloudResources& res) { return res.rebuilds; }
uint32_t shadow_map_updates(const CloudResources& res) { return res.shadow_updates; }

float nearest_instance_distance(const CloudFrameInputs& in) {
  float nearest = INFINITY;
  for (const CloudInstance& inst : in.instances) {
    glm::vec3 wmin, wmax;
    instance_world_bounds(inst, wmin, wmax);
    const glm::vec3 p = in.camera.position;
    nearest = std::min(nearest, glm::distance(p, glm::clamp(p, wmin, wmax)));
  }
  return nearest;
}

void instance_world_bounds(const CloudInstance& inst, glm::vec3& wmin, glm::vec3& wmax) {
  const glm::vec3 lo = inst.asset->bounds_min, hi = inst.asset->bounds_max;
  wmin = glm::vec3(INFINITY), wmax = glm::vec3(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 corner((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const glm::vec3 w = inst.position + glm::normalize(inst.rotation) * (inst.scale * corner);
    wmin = glm::min(wmin, w), wmax = glm::max(wmax, w);
  }
}

std::optional<cumulo::render::LightShadowMap> shadow_plane(const CloudFrameInputs& in, uint32_t texels) {
  const glm::vec3 l = glm::normalize(in.sun_direction);
  if (!in.settings.shadows || in.instances.empty() || l.y < kShadowMinLightHeight) return std::nullopt;
  // The plane under every box; each box's corners projected onto it along the light bound the map.
  float height = INFINITY;
  std::vector<std::pair<glm::vec3, glm::vec3>> boxes;
  for (const CloudInstance& inst : in.instances) {
    glm::vec3 lo, hi;
    instance_world_bounds(inst, lo, hi);
    boxes.emplace_back(lo, hi);
    height = std::min(height, lo.y);
  }
  glm::vec2 lo2(INFINITY), hi2(-INFINITY);
  for (const auto& [lo, hi] : boxes)
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 w((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
      const glm::vec3 q = w + l * ((height - w.y) / l.y);
      lo2 = glm::min(lo2, glm::vec2(q.x, q.z)), hi2 = glm::max(hi2, glm::vec2(q.x, q.z));
    }
  // Square texels: the longer side sets the size; one texel of margin keeps the border unshadowed.
  const float side = std::max(hi2.x - lo2.x, hi2.y - lo2.y) * (1.0f + 2.0f / float(std::max(texels, 4u)));
  const glm::vec2 centre = 0.5f * (lo2 + hi2);
  cumulo::render::LightShadowMap m;
  m.origin = centre - glm::vec2(0.5f * side);
  m.size = glm::vec2(side);
  m.height = height;
  return m;
}

CloudLightOutputs add_cloud_light_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in) {
  CloudLightOutputs out;
  if (in.instances.empty()) return out;
  if (in.instances.size() > kMaxInstances)
    fail("clouds: %zu cloudscape instances, at most %u per frame", in.instances.size(), kMaxInstances);
  if (in.lights.size() > kMaxPointLights)
    fail("clouds: %zu point lights, at most %u per frame", in.lights.size(), kMaxPointLights);
  // Distinct assets in order of first use: slot 0 and, for a second asset, slot 1 (the march binds both).
  std::vector<const CloudAsset*> assets;
  std::vector<uint32_t> slots;
  for (const CloudInstance& inst : in.instances) {
    if (!inst.asset) fail("clouds: a cloudscape instance has no asset");
    auto it = std::find(assets.begin(), assets.end(), inst.asset.get());
    if (it == assets.end()) {
      if (assets.size() == kMaxAssets)
        fail("clouds: more than %u cloudscape assets in one frame (%s, %s, %s): instances may share an asset", kMaxAssets,
             assets[0]->folder.string().c_str(), assets[1]->folder.string().c_str(), inst.asset->folder.string().c_str());
      assets.push_back(inst.asset.get());
      it = assets.end() - 1;
    }
    slots.push_back(uint32_t(it - assets.begin()));
  }
  for (const CloudAsset* a : assets)
    if (a->formats != assets[0]->formats)
      fail("clouds: the cloudscape assets %s and %s use different formats in one frame", assets[0]->folder.string().c_str(),
           a->folder.string().c_str());
  const int asset_slots = int(assets.size());
  const CloudSettings& s = in.settings;
  const VkExtent2D size = graph.output_size();
  const bool bc1 = assets[0]->formats.bc1_field;
  // The BC1 modeling NVDF has no alpha: its coverage thresholds come from the asset's coverage texture.
  const bool coverage_texture = assets[0]->formats.bc1_modeling;
  gpu::Context& ctx = res.ctx;
  CloudResources* r = &res;

  // ---- Persistent resources: assets, noise, light grids, history ----
  auto import_3d = [&](const std::string& name, const gpu::Image& img) {
    const VkExtent3D e = img.extent();
    TextureDesc d = TextureDesc::absolute(img.format(), e.width, e.height, e.depth);
    d.type = cumulo::render::ImageType::Image3D;
    d.mips = img.mips();
    return graph.import_texture(name, d, img.handle(), img.view(), sampled_state());
  };
  std::vector<TextureHandle> modelings, fields, coverages, fairs;
  for (size_t a = 0; a < assets.size(); ++a) {
    const std::string suffix = a ? "." + std::to_string(a) : "";
    modelings.push_back(import_3d("clouds.modeling" + suffix, assets[a]->modeling));
    fields.push_back(import_3d("clouds.field" + suffix, assets[a]->field));
    fairs.push_back(import_3d("clouds.field_fair" + suffix, assets[a]->field_fair));
    if (coverage_texture) coverages.push_back(import_3d("clouds.coverage" + suffix, assets[a]->coverage));
  }
  const TextureHandle noise = import_3d("clouds.noise", res.noise->image);

  const uint32_t n = uint32_t(in.instances.size());
  const glm::uvec3 gs = res.desc.light_grid_size;
  struct GridWork {
    uint32_t first = 0, layers = 0;  // rays: z layers of the instance's slab updated this frame
    uint32_t level_first = 0, level_count = 0;  // sweep: levels updated this frame, in sweep order (0: nearest the light)
  };
  std::vector<GridWork> grids(n);
  if (!res.grid_image || res.grid_instances != n || res.grid_image.extent().width != gs.x ||
      res.grid_image.extent().height != gs.y || res.grid_image.extent().depth != gs.z * n) {
    if (res.grid_image) ctx.wait_idle();  // frames in flight may still sample the old grid (rare: instance count changes)
    res.grid_image = gpu::Image(ctx, gpu::ImageDesc::tex3d(gs.x, gs.y, gs.z * n, kGridFormat,
                                                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1,
                                                           "clouds.light_grid"));
    res.grid_texture = {"clouds.light_grid", TextureDesc::absolute(kGridFormat, gs.x, gs.y, gs.z * n),
                        res.grid_image.handle(), res.grid_image.view(), ResourceState::undefined()};
    res.grid_instances = n;
    for (auto& g : res.grids) g = {};
  }
  const float cos_threshold = std::cos(glm::radians(s.sun_rebuild_degrees));
  const glm::vec3 sun_world = glm::normalize(in.sun_direction);
  for (uint32_t i = 0; i < n; ++i) {
    CloudResources::LightGrid& g = res.grids[i];
    const CloudInstance& inst = in.instances[i];
    const glm::vec3 sun_asset = glm::normalize(glm::inverse(glm::normalize(inst.rotation)) * sun_world);
    const uint64_t key = instance_key(inst, res.desc);
    const bool rebuild = !g.valid || in.rebuild_light_grid || key != g.key || glm::dot(sun_asset, g.sun) < cos_threshold;
    const uint32_t slab = gs.z / res.desc.light_grid_divisions;
    // The sweep amortizes by levels over the whole grid (light_grid_sweep.comp says why).
    const uint32_t levels_per_frame = (gs.y + res.desc.light_grid_divisions - 1) / res.desc.light_grid_divisions;
    // The sweep reads the noise by its mean, so the wind does not move it: with the sun still for a
    // whole cycle of levels the grid is current and the frame's update would rewrite the same values.
    // (The rays method samples the scrolling noise and keeps updating.)
    g.frames_same_sun = sun_asset == g.last_sun ? g.frames_same_sun + 1 : 0;
    g.last_sun = sun_asset;
    const bool current = s.light_grid_method == CloudLightGridMethod::Sweep && !s.light_grid_always_update &&
                         g.frames_same_sun >= res.desc.light_grid_divisions;
    if (rebuild) {
      grids[i].first = 0, grids[i].layers = gs.z;
      grids[i].level_first = 0, grids[i].level_count = gs.y;
      g.sun = sun_asset, g.key = key, g.valid = true;
      g.frames_same_sun = res.desc.light_grid_divisions;  // every level computed with this sun
      ++res.rebuilds;
    } else if (current) {
      grids[i].first = 0, grids[i].layers = 0;
      grids[i].level_first = 0, grids[i].level_count = 0;
    } else if (s.light_grid_method == CloudLightGridMethod::Sweep) {
      grids[i].first = 0, grids[i].layers = gs.z;
      grids[i].level_first = std::min(gs.y, uint32_t(in.frame_index % res.desc.light_grid_divisions) * levels_per_frame);
      grids[i].level_count = std::min(levels_per_frame, gs.y - grids[i].level_first);
    } else {
      grids[i].first = uint32_t(in.frame_index % res.desc.light_grid_divisions) * slab;
      grids[i].layers = slab;
    }
  }
  // Partial updates keep the other slabs / levels: the graph carries the grid's content and state across frames.
  TextureHandle grid = graph.import_persistent(res.grid_texture);
  // The light passes read the instances of this frame's parameters; add_cloud_passes writes the block
  // again (history, reprojection) before the frame is submitted, with the same instances.
  const gpu::Buffer& ubo = res.ubo[in.slot % gpu::kFramesInFlight];
  const shared::CloudParams params = make_params(res, in, size, false, slots);
  std::memcpy(ubo.mapped(), &params, sizeof params);
  const VkBuffer ubo_handle = ubo.handle();
  constexpr VkDeviceSize kUboSize = sizeof(shared::CloudParams);

  // ---- 1. Light grid ----
  const bool sweep = s.light_grid_method == CloudLightGridMethod::Sweep;
  gpu::Pipeline* grid_pipe = sweep ? &res.sweep(bc1, coverage_texture) : &res.grid(bc1, coverage_texture);
  const CloudResourcesDesc rdesc = res.desc;
  // Sweep order per instance: levels from the light's side; the sun and the sky share one sweep when
  // both point up (or both down), else each channel gets its own; the own cloud's sum away from the sun
  // (channel 4) sweeps from the other side.
  struct SweepPlan {
    uint32_t channels[3] = {3, 4, 0};
    bool down[3] = {true, false, true};  // true: from the top level down
  };
  std::vector<SweepPlan> plans(n);
  for (uint32_t i = 0; i < n; ++i) {
    const glm::mat3 to_asset = glm::mat3(glm::inverse(glm::normalize(in.instances[i].rotation)));
    const bool sun_up = (to_asset * sun_world).y >= 0.0f, sky_up = (to_asset * glm::vec3(0, 1, 0)).y >= 0.0f;
    if (sun_up == sky_up) plans[i] = {{3, 4, 0}, {sun_up, !sun_up, sun_up}};
    else plans[i] = {{1, 2, 4}, {sun_up, sky_up, !sun_up}};
  }
  bool grid_work = false;
  for (const GridWork& w : grids) grid_work |= w.layers > 0 && (!sweep || w.level_count > 0);
  if (grid_work) graph.add_pass("clouds.light_grid", Queue::Compute,
      [&](PassBuilder& b) {
        for (size_t a = 0; a < modelings.size(); ++a) {
          b.read(modelings[a], Usage::Sampled);
          b.read(fields[a], Usage::Sampled);
        }
        for (TextureHandle t : coverages) b.read(t, Usage::Sampled);
        b.read(noise, Usage::Sampled);
        grid = b.read_write(grid, Usage::StorageWrite);
      },
      [r, grid_pipe, grids, plans, sweep, grid, modelings, fields, coverages, slots, noise, ubo_handle, rdesc](PassContext& c) {
        const VkExtent3D e = c.extent(grid);
        // Each instance's dispatches read its own asset (push descriptors: rebound when the asset changes).
        uint32_t bound = UINT32_MAX;
        auto bind = [&](uint32_t a) {
          if (a == bound) return;
          bound = a;
          Bindings bindings(*grid_pipe);
          bindings.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
              .sampled(CLOUD_BINDING_MODELING, c.view(modelings[a]), r->linear_clamp, c.layout(modelings[a]))
              .sampled(CLOUD_BINDING_FIELD, c.view(fields[a]), r->linear_clamp, c.layout(fields[a]))
              .sampled(CLOUD_BINDING_NOISE, c.view(noise), r->linear_repeat, c.layout(noise))
              .storage(CLOUD_BINDING_GRID_OUT, c.view(grid));
          if (!coverages.empty())
            bindings.sampled(CLOUD_BINDING_COVERAGE, c.view(coverages[a]), r->linear_clamp, c.layout(coverages[a]));
          bindings.push(r->ctx, c.cmd());
        };
        for (uint32_t i = 0; i < grids.size(); ++i) {
          if (grids[i].layers == 0 || (sweep && grids[i].level_count == 0)) continue;
          bind(slots[i]);
          shared::CloudLightGridPush pc{};
          if (!sweep) {
            pc.region = glm::uvec4(i, grids[i].first, grids[i].layers, 0);
            pc.grid = glm::vec4(float(rdesc.light_grid_sun_steps), float(rdesc.light_grid_sky_steps),
                                float(rdesc.light_grid_size.z), 0.0f);
            grid_pipe->push_constants(c.cmd(), pc);
            grid_pipe->dispatch_threads(c.cmd(), e.width, e.height, grids[i].layers);
            continue;
          }
          // One dispatch per level; each level reads the one before it (written by the previous
          // dispatch of this pass): the only barriers recorded inside a cloud pass.
          for (uint32_t sweep_index = 0; sweep_index < 3 && plans[i].channels[sweep_index]; ++sweep_index)
            for (uint32_t k = grids[i].level_first; k < grids[i].level_first + grids[i].level_count; ++k) {
              const uint32_t level = plans[i].down[sweep_index] ? e.height - 1 - k : k;
              if (k > grids[i].level_first || sweep_index > 0 || i > 0)
                gpu::cmd_memory_barrier(c.cmd(), VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
              pc.region = glm::uvec4(i, grids[i].first, grids[i].layers, level);
              pc.grid = glm::vec4(float(rdesc.light_grid_sweep_samples), float(plans[i].channels[sweep_index]),
                                  float(rdesc.light_grid_size.z), 0.0f);
              grid_pipe->push_constants(c.cmd(), pc);
              grid_pipe->dispatch_threads(c.cmd(), e.width, 1, grids[i].layers);
            }
        }
      });


  // ---- 1b. The clouds' shadow on the scene (shadow_map.comp) ----
  // A persistent texture, recomputed only when the light grid changed this frame or the plane moved
  // (the map is the grid's sums at the boxes' entries: nothing else changes it).
  if (const std::optional<cumulo::render::LightShadowMap> plane = shadow_plane(in, res.desc.shadow_map_size)) {
    const uint32_t sm = res.desc.shadow_map_size;
    if (!res.shadow_image) {
      res.shadow_image = gpu::Image(ctx, gpu::ImageDesc::tex2d(sm, sm, VK_FORMAT_R16_SFLOAT,
                                                               VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1,
                                                               "clouds.shadow_map"));
      res.shadow_texture = {"clouds.shadow_map", TextureDesc::absolute(VK_FORMAT_R16_SFLOAT, sm, sm),
                            res.shadow_image.handle(), res.shadow_image.view(), ResourceState::undefined()};
    }
    TextureHandle shadow = graph.import_persistent(res.shadow_texture);
    const glm::vec4 key(plane->origin, plane->size.x, plane->height);
    const bool stale = grid_work || !res.shadow_valid || key != res.shadow_key || sun_world != res.shadow_sun;
    if (stale) {
      gpu::Pipeline* pipe = res.shadow_pipe;
      shared::CloudShadowPush pc{};
      pc.plane = glm::vec4(plane->origin, plane->size);
      pc.light = glm::vec4(sun_world, plane->height);
      graph.add_pass("clouds.shadow_map", Queue::Compute,
          [&](PassBuilder& b) {
            b.read(grid, Usage::Sampled);
            shadow = b.write(shadow, Usage::StorageWrite);
            b.side_effect();  // kept for the frames that reuse it
          },
          [r, pipe, grid, shadow, ubo_handle, pc](PassContext& c) {
            Bindings(*pipe)
                .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
                .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
                .storage(CLOUD_BINDING_SHADOW_OUT, c.view(shadow))
                .push(r->ctx, c.cmd());
            pipe->push_constants(c.cmd(), pc);
            const VkExtent3D e = c.extent(shadow);
            pipe->dispatch_threads(c.cmd(), e.width, e.height);
          });
      res.shadow_key = key;
      res.shadow_sun = sun_world;
      res.shadow_valid = true;
      ++res.shadow_updates;
    }
    out.shadow = *plane;
    out.shadow.texture = shadow;
  }
  out.grid = grid;
  out.modelings = std::move(modelings);
  out.fields = std::move(fields);
  out.fairs = std::move(fairs);
  out.coverages = std::move(coverages);
  out.noise = noise;
  out.slots = std::move(slots);
  out.asset_slots = asset_slots;
  out.bc1 = bc1;
  out.coverage_texture = coverage_texture;
  return out;
}

TextureHandle add_cloud_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, TextureHandle hdr,
                               TextureHandle depth, CloudPassOutputs* outputs, const CloudLightOutputs* light) {
  if (in.instances.empty()) return hdr;
  CloudLightOutputs own;
  if (!light) {
    own = add_cloud_light_passes(res, graph, in);
    light = &own;
  }
  const std::vector<TextureHandle>& modelings = light->modelings;
  const std::vector<TextureHandle>& fields = light->fields;
  const std::vector<TextureHandle>& coverages = light->coverages;
  const std::vector<TextureHandle>& fairs = light->fairs;
  const bool coverage_texture = light->coverage_texture;
  const TextureHandle modeling = modelings[0], field = fields[0], noise = light->noise, grid = light->grid;
  const std::vector<uint32_t>& slots = light->slots;
  const int asset_slots = light->asset_slots;
  const bool bc1 = light->bc1;
  const CloudSettings& s = in.settings;
  const VkExtent2D size = graph.output_size();
  CloudResources* r = &res;
  const bool terrain = s.terrain_shadow && in.terrain_depth.valid();
  const TextureHandle terrain_depth = in.terrain_depth;

  HistoryImports history;
  if (s.temporal) history = import_history(res, graph, in.camera_cut);
  else res.history_on = false;

  // Reprojection: the marched pixel of each BxB block this frame, in the order of a Bayer matrix (each
  // pixel once every B*B frames, neighbours far apart in time).
  const uint32_t block = reprojection_block(s);
  HistoryImports recon;
  glm::uvec2 sub_offset{0, 0};
  if (block > 1) {
    if (in.camera_cut || res.recon_block != block) res.recon_history.invalidate();
    const cumulo::render::HistoryHandles h = res.recon_history.import(res.ctx, graph);
    recon = {h.previous, h.current, h.valid};
    sub_offset = reprojection_offset(block, in.frame_index);
  }
  res.recon_block = block > 1 ? block : 0;

  const gpu::Buffer& ubo = res.ubo[in.slot % gpu::kFramesInFlight];
  const shared::CloudParams params = make_params(res, in, size, history.valid, slots);
  std::memcpy(ubo.mapped(), &params, sizeof params);
  res.prev_view_proj = in.camera.view_proj;
  const VkBuffer ubo_handle = ubo.handle();
  constexpr VkDeviceSize kUboSize = sizeof(shared::CloudParams);
  // ---- 2. March (one pass, or near/far + merge) ----
  // `front` (far segment only): the near layer, read for its transmittance (early exit).
  auto add_march = [&](const char* name, int segment, TextureHandle& color, TextureHandle& cdepth,
                       TextureHandle front = {}, uint32_t sub_block = 1) {
    gpu::Pipeline* pipe =
        &res.march(s.ablation, segment, bc1, s.distance_noise_mip, s.light_sample_noise_mean, asset_slots, terrain,
                   coverage_texture);
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
          b.read(depth, Usage::Sampled);
          if (front.valid()) b.read(front, Usage::Sampled);
          if (terrain) b.read(terrain_depth, Usage::Sampled);
          color = b.write(color, Usage::StorageWrite);
          cdepth = b.write(cdepth, Usage::StorageWrite);
        },
        [r, pipe, grid, modeling, field, modelings, fields, coverages, fairs, noise, depth, color, cdepth, front, ubo_handle, sub_block,
         sub_offset, size, terrain, terrain_depth](PassContext& c) {
          Bindings bind(*pipe);
          bind.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
              .sampled(CLOUD_BINDING_MODELING, c.view(modeling), r->linear_clamp, c.layout(modeling))
              .sampled(CLOUD_BINDING_FIELD, c.view(field), r->linear_clamp, c.layout(field))
              .sampled(CLOUD_BINDING_NOISE, c.view(noise), r->linear_repeat, c.layout(noise))
              .sampled(CLOUD_BINDING_SCENE_DEPTH, c.view(depth), r->nearest_clamp, c.layout(depth))
              .storage(CLOUD_BINDING_OUT_COLOR, c.view(color))
              .storage(CLOUD_BINDING_OUT_DEPTH, c.view(cdepth))
              .sampled(CLOUD_BINDING_LIGHT_GRID, c.view(grid), r->linear_clamp, c.layout(grid));
          if (front.valid()) bind.sampled(CLOUD_BINDING_NEAR_IN, c.view(front), r->nearest_clamp, c.layout(front));
          if (terrain)
            bind.sampled(CLOUD_BINDING_TERRAIN_DEPTH, c.view(terrain_depth), r->nearest_clamp, c.layout(terrain_depth));
          if (modelings.size() > 1)
            bind.sampled(CLOUD_BINDING_MODELING_1, c.view(modelings[1]), r->linear_clamp, c.layout(modelings[1]))
                .sampled(CLOUD_BINDING_FIELD_1, c.view(fields[1]), r->linear_clamp, c.layout(fields[1]));
          for (size_t a = 0; a < coverages.size(); ++a)
            bind.sampled(a ? CLOUD_BINDING_COVERAGE_1 : CLOUD_BINDING_COVERAGE, c.view(coverages[a]), r->linear_clamp,
                         c.layout(coverages[a]));
          for (size_t a = 0; a < fairs.size(); ++a)
            bind.sampled(a ? CLOUD_BINDING_FIELD_FAIR_1 : CLOUD_BINDING_FIELD_FAIR, c.view(fairs[a]), r->linear_clamp,
                         c.layout(fairs[a]));
          bind.push(r->ctx, c.cmd());
          const VkExtent3D e = c.extent(color);
          if (sub_block > 1) {
            // Full-resolution rays, one per block: the image written is the sub-sampled one.
            shared::CloudMarchPush pc = target_push({size.width, size.height, 1});
            pc.sub = glm::vec4(float(sub_block), float(sub_offset.x), float(sub_offset.y), 0.0f);
            pipe->push_constants(c.cmd(), pc);
          } else {
            pipe->push_constants(c.cmd(), target_push(e));
          }
          pipe->dispatch_threads(c.cmd(), e.width, e.height);
        });
  };
  // The full-resolution march, sub-sampled and reconstructed when reprojection is on.
  auto add_full_res_march = [&](const char* name, int segment, TextureHandle& color, TextureHandle& cdepth,
                                TextureHandle front = {}) {
    if (block <= 1) return add_march(name, segment, color, cdepth, front);
    const uint32_t sw = (size.width + block - 1) / block, sh = (size.height + block - 1) / block;
    TextureHandle sub_c = graph.create_texture("clouds.sub_color", TextureDesc::absolute(kColorFormat, sw, sh));
    TextureHandle sub_d = graph.create_texture("clouds.sub_depth", TextureDesc::absolute(kDepthFormat, sw, sh));
    add_march(name, segment, sub_c, sub_d, front, block);
    TextureHandle next = recon.next;
    add_reconstruct_pass(graph, res.ctx, "clouds.reconstruct",
                         {r->recon_pipe, ubo_handle, sub_c, sub_d, recon.prev, depth, block, sub_offset, recon.valid}, next,
                         cdepth);
    color = next;
  };

  TextureHandle color = graph.create_texture("clouds.color", TextureDesc::relative(kColorFormat));
  TextureHandle cdepth = graph.create_texture("clouds.depth", TextureDesc::relative(kDepthFormat));
  // 40/60 Hz with no cloudscape box within the split distance (the ground view: clouds from 600 m up):
  // the near segment is empty, so its half-resolution march and the merge are skipped and the far
  // march runs over the whole ray (the same samples: none lie nearer than the split). The split
  // debug view keeps both, to show them.
  const bool near_empty = s.split && s.skip_empty_near && s.debug != CloudDebugView::Split &&
                          nearest_instance_distance(in) >= s.split_distance_m;
  if (!s.split) {
    add_full_res_march("clouds.march", CLOUD_SEGMENT_ALL, color, cdepth);
  } else if (near_empty) {
    add_full_res_march("clouds.march_far", CLOUD_SEGMENT_ALL, color, cdepth);
  } else {
    TextureHandle near_c = graph.create_texture("clouds.near_color", TextureDesc::relative(kColorFormat, 0.5f));
    TextureHandle near_d = graph.create_texture("clouds.near_depth", TextureDesc::relative(kDepthFormat, 0.5f));
    TextureHandle far_c = graph.create_texture("clouds.far_color", TextureDesc::relative(kColorFormat));
    TextureHandle far_d = graph.create_texture("clouds.far_depth", TextureDesc::relative(kDepthFormat));
    add_march("clouds.march_near", CLOUD_SEGMENT_NEAR, near_c, near_d);
    add_full_res_march("clouds.march_far", CLOUD_SEGMENT_FAR, far_c, far_d, near_c);
    gpu::Pipeline* merge = res.merge_pipe;
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
              .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
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

  // ---- 3. Temporal accumulation ----
  TextureHandle final_color = color;
  if (s.temporal) {
    gpu::Pipeline* pipe = res.temporal_pipe;
    TextureHandle prev = history.prev, next = history.next;
    graph.add_pass("clouds.temporal", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(color, Usage::Sampled);
          b.read(cdepth, Usage::Sampled);
          b.read(prev, Usage::Sampled);
          next = b.write(next, Usage::StorageWrite);
        },
        [r, pipe, color, cdepth, prev, next, ubo_handle](PassContext& c) {
          Bindings(*pipe)
              .ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
              .sampled(CLOUD_BINDING_CURRENT, c.view(color), r->nearest_clamp, c.layout(color))
              .sampled(CLOUD_BINDING_CURRENT_DEPTH, c.view(cdepth), r->nearest_clamp, c.layout(cdepth))
              .sampled(CLOUD_BINDING_HISTORY, c.view(prev), r->linear_clamp, c.layout(prev))
              .storage(CLOUD_BINDING_ACCUM_OUT, c.view(next))
              .push(r->ctx, c.cmd());
          const VkExtent3D e = c.extent(next);
          pipe->push_constants(c.cmd(), target_push(e));
          pipe->dispatch_threads(c.cmd(), e.width, e.height);
        });
    final_color = next;
  }

  // ---- 4. Composite over the scene colour ----
  const bool sky = in.sky_color.valid() && in.sky_depth.valid();
  const bool aerial = in.aerial.valid();
  gpu::Pipeline* comp = res.composite_pipes[sky ? 1 : 0][aerial ? 1 : 0];
  const TextureHandle sky_color = in.sky_color, sky_depth = in.sky_depth, aerial_tex = in.aerial;
  graph.add_pass("clouds.composite", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(final_color, Usage::Sampled);
        b.read(cdepth, Usage::Sampled);
        b.read(grid, Usage::Sampled);
        if (sky) {
          b.read(sky_color, Usage::Sampled);
          b.read(sky_depth, Usage::Sampled);
          b.read(depth, Usage::Sampled);
        }
        if (aerial) b.read(aerial_tex, Usage::Sampled);
        hdr = b.read_write(hdr, Usage::StorageWrite);
      },
      [r, comp, final_color, cdepth, grid, hdr, ubo_handle, sky, sky_color, sky_depth, depth, aerial,
       aerial_tex](PassContext& c) {
        Bindings bind(*comp);
        bind.ubo(CLOUD_BINDING_PARAMS, ubo_handle, kUboSize)
            .sampled(CLOUD_BINDING_CLOUDS, c.view(final_color), r->nearest_clamp, c.layout(final_color))
            .sampled(CLOUD_BINDING_CLOUD_DEPTH, c.view(cdepth), r->nearest_clamp, c.layout(cdepth))
            .sampled(CLOUD_BINDING_DEBUG_GRID, c.view(grid), r->linear_clamp, c.layout(grid))
            .storage(CLOUD_BINDING_HDR, c.view(hdr));
        if (sky)
          bind.sampled(CLOUD_BINDING_SKY_COLOR, c.view(sky_color), r->linear_clamp, c.layout(sky_color))
              .sampled(CLOUD_BINDING_SKY_DEPTH, c.view(sky_depth), r->nearest_clamp, c.layout(sky_depth))
              .sampled(CLOUD_BINDING_SCENE_DEPTH_COMPOSITE, c.view(depth), r->nearest_clamp, c.layout(depth));
        if (aerial) bind.sampled(CLOUD_BINDING_AERIAL, c.view(aerial_tex), r->linear_clamp, c.layout(aerial_tex));
        bind.push(r->ctx, c.cmd());
        const VkExtent3D e = c.extent(hdr);
        comp->push_constants(c.cmd(), target_push(e));
        comp->dispatch_threads(c.cmd(), e.width, e.height);
      });
  if (outputs) *outputs = {final_color, cdepth};
  return hdr;
}

}  // namespace cumulo::clouds::render
