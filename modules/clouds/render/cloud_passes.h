#pragma once
// Inside the voxel-cloud renderer (cloud_renderer.h): the persistent resources and the frame's passes as
// named steps, each in the file that owns it, called in order by add_cloud_light_passes and
// add_cloud_passes (cloud_renderer.cpp), the way the render graph's compiler runs its steps:
//   cloud_light_passes.cpp    0. the assets and the noise imported   1. the light grid   1a. its multiple scattering
//                             solved (the solve lighting)   1b. the shadow map
//   cloud_march_passes.cpp    2. the march (one pass, or near/far and their merge; sub-sampled + reconstructed)
//   cloud_resolve_passes.cpp  3. temporal accumulation   4. the composite over the scene colour
// Not for use outside render/.
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/render/history.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/render/pass_bindings.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::render {

using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::ResourceState;
using cumulo::render::TextureDesc;
using cumulo::render::Usage;
using Bindings = PassBindings;

inline constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // rgb radiance, a transmittance
inline constexpr VkFormat kDepthFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // opacity-0.5 distance, steps, segment end
inline constexpr VkFormat kGridFormat = VK_FORMAT_R16G16B16A16_SFLOAT;   // summed density toward the sun, the sky, the sun in the own cloud, away from the sun in it

// The state an imported image is in when the graph starts and the next user finds it: sampled by
// compute or fragment shaders.
inline ResourceState sampled_state() { return ResourceState::shader_read_only(); }

struct CloudResources {
  // One instance's slab of the light-grid image.
  struct LightGrid {
    bool valid = false;   // has been fully built
    glm::vec3 sun{0.0f};  // sun direction (asset space) of the last full rebuild
    uint64_t key = 0;     // what the grid depends on besides the sun (asset, transform, density)
    glm::vec3 last_sun{0.0f};       // sun direction of the last frame (asset space)
    uint32_t frames_same_sun = 0;   // frames since the sun or the weather last moved (the sweep is current after a cycle)
    glm::vec3 weather{0.0f};        // the instance's density, dissipation and coverage at the last full rebuild
    glm::vec3 last_weather{0.0f};   // ... of the last frame
    uint32_t sweep_phase = 0;       // the frame index (mod the divisions) at which the sweep's cycle starts its first level
    uint32_t sweep_left = 0;        // frames of sweep still owed to a change of the asset's images (asset_grew)
  };
  // ablation, segment, bc1 SDF, distance noise mip, mean-noise light samples, asset slots, terrain shadow,
  // coverage texture (the BC1 modeling NVDF), the solved multiple scattering (MS_FIELD)
  using MarchKey = std::tuple<int, int, bool, bool, bool, int, bool, bool, bool>;

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
  // CloudSettings::ms_solve: the diffusion solve's coefficients and fluence, the light grid's size and stacking
  // (light_grid_diffusion.comp); valid once solved after the image was made.
  gpu::Image ms_image;
  cumulo::render::PersistentTexture ms_texture;
  bool ms_valid = false;
  uint64_t ms_frame = 0;  // the frame of the last solve
  // What the march reads of the light grids at a sample (light_grid_local.comp): the other instances' shadow, the own
  // sky and away sums; the light grid's size and stacking. Valid once written for the grid's instances with
  // `local_shadows` (CloudSettings::instance_shadows); after that, updated where the grids changed.
  gpu::Image local_image;
  cumulo::render::PersistentTexture local_texture;
  bool local_valid = false;
  bool local_shadows = false;
  gpu::Pipeline* local_pipe = nullptr;
  // Temporal accumulation: the graph's history pair (engine/render/history.h).
  cumulo::render::GpuHistory history{"clouds.history", kColorFormat, 1.0f,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  bool history_on = false;  // the last frame accumulated (a frame without temporal breaks the history)
  // Reprojection of the sub-sampled march: the last frame's reconstruction.
  cumulo::render::GpuHistory recon_history{"clouds.reprojection", kColorFormat, 1.0f,
                                           VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  uint32_t recon_block = 0;  // block size of the last frame's reconstruction (0: none)
  // Frames since the picture last changed in a way the reprojection cannot follow (a camera cut, a point light, a
  // light-grid rebuild: an instance moved or faded, the weather's coverage, the sun past the rebuild angle).
  uint32_t frames_settled = 0;
  uint32_t settled_rebuilds = 0;  // `rebuilds` when frames_settled last started
  gpu::Pipeline* recon_pipe = nullptr;
  gpu::Pipeline* recon_merge_pipe = nullptr;  // the far segment's, merging the near layer in (MERGE_NEAR)
  // The same two accumulating their result as well (TEMPORAL: the temporal pass's work, one full-resolution pass less).
  gpu::Pipeline* recon_temporal_pipe = nullptr;
  gpu::Pipeline* recon_merge_temporal_pipe = nullptr;
  // The same for the near segment of the 40/60 Hz split (half resolution; its ray ends at the split).
  cumulo::render::GpuHistory near_history{"clouds.reprojection_near", kColorFormat, 0.5f,
                                          VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  uint32_t near_block = 0;
  gpu::Pipeline* recon_near_pipe = nullptr;
  glm::mat4 prev_view_proj{1.0f};
  gpu::Pipeline* grid_pipe = nullptr;
  gpu::Pipeline* temporal_pipe = nullptr;
  gpu::Pipeline* merge_pipe = nullptr;
  // [with the 2.5D sky (SKY_LAYER)][with the aerial froxels (AERIAL)][clouds below the output's size (UPSAMPLE),
  // made on first use][a debug view that replaces the picture (DEBUG_VIEWS: steps, light grid; made on first
  // use): on a CPU device an unused branch still costs, the light grid's fetch a third of the pass]
  // [the Envelope method's clouds (ENVELOPE: 0 none, 1 one layer at the output's size, 2 the split's near and far
  // passes, 3 one layer below the output's size)]
  gpu::Pipeline* composite_pipes[2][2][2][2][4] = {};
  gpu::Pipeline* shadow_pipe = nullptr;
  // A frame without voxel instances (the 2.5D sky or the envelope clouds alone): the composite's light grid.
  gpu::Image empty_grid;
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
                       int asset_slots = 1, bool terrain_shadow = false, bool coverage_texture = false,
                       bool ms_field = false) {
    MarchKey key{int(a), segment, bc1, distance_mip, mean_light_noise, asset_slots, terrain_shadow, coverage_texture, ms_field};
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
                 {"COVERAGE_TEXTURE", coverage_texture ? "1" : "0"},
                 {"MS_FIELD", ms_field ? "1" : "0"}};
    d.name = std::string("clouds.march (") + ablation_name(a) + ", " + kSegments[segment] + (bc1 ? ", bc1 sdf" : "") +
             (ms_field ? ", solved multiple scattering" : "") +
             (distance_mip ? "" : ", mip 0") + (mean_light_noise ? "" : ", sampled light noise") +
             (asset_slots > 1 ? ", " + std::to_string(asset_slots) + " assets" : "") + (terrain_shadow ? ", terrain shadow" : "") +
             (coverage_texture ? ", coverage texture" : "") + ")";
    gpu::Pipeline& p = library.compute(d);
    march_pipes[key] = &p;
    return p;
  }
  gpu::Pipeline& composite(bool sky, bool aerial, bool upsample, bool debug_views = false, int envelope = 0) {
    gpu::Pipeline*& p = composite_pipes[sky][aerial][upsample][debug_views][envelope];
    if (!p) {
      gpu::ComputePipelineDesc d{.shader = "clouds/composite_apply.comp",
                                 .defines = {{"SKY_LAYER", sky ? "1" : "0"},
                                             {"AERIAL", aerial ? "1" : "0"},
                                             {"UPSAMPLE", upsample ? "1" : "0"},
                                             {"DEBUG_VIEWS", debug_views ? "1" : "0"}},
                                 .name = std::string("clouds.composite") + (sky ? " (2.5D sky)" : "") +
                                         (aerial ? " (aerial froxels)" : "") + (upsample ? " (upsampled)" : "") +
                                         (debug_views ? " (debug views)" : "") +
                                         (envelope == 1 ? " (envelope)" : envelope == 2 ? " (envelope, split)"
                                          : envelope == 3 ? " (envelope, upsampled)" : "")};
      // Only a composite with the envelope's layer names its defines: the others' sources, and so their cached and
      // compiled code, stay what they were.
      if (envelope > 0) {
        d.defines.push_back({"ENVELOPE", "1"});
        d.defines.push_back({"ENVELOPE_SPLIT", envelope == 2 ? "1" : "0"});
        d.defines.push_back({"ENVELOPE_UPSAMPLE", envelope >= 2 ? "1" : "0"});
      }
      p = &library.compute(d);
    }
    return *p;
  }
  // The light grid's shaders (the sweep, the talk's rays, the solve) sample the density: one pipeline per SDF form
  // and coverage source, named "NAME (variant)".
  gpu::Pipeline& light_pipeline(int kind, const char* shader, const std::string& name, bool bc1, bool coverage_texture) {
    MarchKey key{kind, 0, bc1, true, true, 1, false, coverage_texture, false};
    auto it = march_pipes.find(key);
    if (it != march_pipes.end()) return *it->second;
    const std::string variant =
        std::string(bc1 ? "bc1 sdf" : "") + (bc1 && coverage_texture ? ", " : "") + (coverage_texture ? "coverage texture" : "");
    gpu::Pipeline& p = library.compute({.shader = shader,
                                        .defines = {{"SDF_BC1", bc1 ? "1" : "0"}, {"COVERAGE_TEXTURE", coverage_texture ? "1" : "0"}},
                                        .name = variant.empty() ? name : name + " (" + variant + ")"});
    march_pipes[key] = &p;
    return p;
  }
  gpu::Pipeline& sweep(bool bc1, bool coverage_texture = false) {
    return light_pipeline(-2, "clouds/light_grid_sweep.comp", "clouds.light_grid_sweep", bc1, coverage_texture);
  }
  gpu::Pipeline& ms_solve(bool bc1, bool coverage_texture = false) {
    return light_pipeline(-3, "clouds/light_grid_diffusion.comp", "clouds.ms_solve", bc1, coverage_texture);
  }
  gpu::Pipeline& grid(bool bc1, bool coverage_texture = false) {
    return light_pipeline(-1, "clouds/light_grid_update.comp", "clouds.light_grid", bc1, coverage_texture);
  }
};


// The size the march and its reconstruction render at: the output's times the frame's resolution scale.
inline VkExtent2D march_extent(const RenderGraph& graph, const CloudFrameInputs& in) {
  return cumulo::render::relative_extent(graph.output_size(), in.resolution_scale);
}

inline shared::CloudMarchPush target_push(VkExtent3D e) {
  shared::CloudMarchPush pc{};
  pc.target = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
  pc.sub = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
  return pc;
}

// The frame's parameter block written to this slot's uniform buffer; its handle.
shared::CloudParams make_params(const CloudResources& res, const CloudFrameInputs& in, VkExtent2D size,
                                bool history_valid, const std::vector<uint32_t>& slots);
inline VkBuffer write_params(CloudResources& res, const CloudFrameInputs& in, VkExtent2D size, bool history_valid,
                             const std::vector<uint32_t>& slots) {
  const gpu::Buffer& ubo = res.ubo[in.slot % gpu::kFramesInFlight];
  const shared::CloudParams params = make_params(res, in, size, history_valid, slots);
  std::memcpy(ubo.mapped(), &params, sizeof params);
  return ubo.handle();
}
inline constexpr VkDeviceSize kParamsSize = sizeof(shared::CloudParams);

// Temporal history: the graph's ping-pong pair (last frame's result as `prev`, this frame's target as
// `next`). Invalid on the first frame, after a resize, a camera cut or a frame without accumulation.
struct HistoryImports {
  TextureHandle prev, next;
  bool valid = false;
};
inline HistoryImports import_history(CloudResources& res, RenderGraph& graph, bool camera_cut, float scale) {
  if (camera_cut || !res.history_on) res.history.invalidate();
  res.history.set_scale(scale);  // a new scale replaces the pair (history invalid)
  const cumulo::render::HistoryHandles h = res.history.import(res.ctx, graph);
  res.history_on = true;
  return {h.previous, h.current, h.valid};
}


// ---- cloud_light_passes.cpp ----
// 0. The frame's distinct assets (slot 0 and, for a second one, slot 1) and the noise, imported; throws
// for too many instances, lights or assets, or assets of different formats.
CloudLightOutputs import_cloud_assets(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in);
// Which slabs (rays) or levels (sweep) of each instance's grid this frame updates, and the sweeps' order.
struct LightGridWork {
  struct Grid {
    uint32_t first = 0, layers = 0;  // rays: z layers of the instance's slab updated this frame
    uint32_t level_first = 0, level_count = 0;  // sweep: levels updated this frame, in sweep order (0: nearest the light)
  };
  // Sweep order per instance: levels from the light's side; the sun and the sky share one sweep when
  // both point up (or both down), else each channel gets its own; the own cloud's sum away from the sun
  // (channel 4) sweeps from the other side.
  struct SweepPlan {
    uint32_t channels[3] = {3, 4, 0};
    bool down[3] = {true, false, true};  // true: from the top level down
  };
  std::vector<Grid> grids;
  std::vector<SweepPlan> plans;
  bool any = false;      // some grid changes this frame
  bool rebuilt = false;  // some grid is rebuilt whole this frame
};
// Also (re)creates the grids' image when the instance count or size changed.
LightGridWork plan_light_grids(CloudResources& res, const CloudFrameInputs& in);
// 1. The light grid pass (none when nothing changes); returns the grid's new version.
TextureHandle add_light_grid_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                  const LightGridWork& work, const CloudLightOutputs& assets, TextureHandle grid,
                                  VkBuffer ubo);
// 1a. What the march reads of the light grids at a sample (light_grid_local.comp): written whole when a grid is rebuilt,
// the image is new or the instances' shadows were switched, else where the grids were updated this frame; returns
// its new version.
TextureHandle add_light_local_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                   const LightGridWork& work, TextureHandle grid, VkBuffer ubo);
// 1b. The multiple scattering solved on the light grid (CloudSettings::ms_solve; light_grid_diffusion.comp), when
// the grid changed or the solve's image is new; returns its new version (invalid without ms_solve).
TextureHandle add_ms_solve_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                const LightGridWork& work, const CloudLightOutputs& assets, VkBuffer ubo);
// 1c. The clouds' shadow on the scene (out.shadow; recomputed when the grid changed or the plane moved).
void add_shadow_map_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in, bool grid_changed,
                         VkBuffer ubo, CloudLightOutputs& out);

// ---- cloud_march_passes.cpp ----
// The reprojection of the sub-sampled march: the block (1: none), this frame's pixel of each block, the
// last frame's reconstruction.
struct Reprojection {
  uint32_t block = 1;
  glm::uvec2 sub_offset{0, 0};
  HistoryImports history;
  bool settled = false;  // ReconstructInputs::settled for the full-resolution march
  // Whether the 40/60 Hz near segment is marched this frame (no cloudscape box within the split distance: skipped),
  // and its reprojection (half resolution; CloudSettings::near_reprojection_block): 1, every pixel.
  bool near_runs = false;
  uint32_t near_block = 1;
  glm::uvec2 near_offset{0, 0};
  HistoryImports near_history;
};
Reprojection import_reprojection(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in);
// 2. The march: its colour (rgb radiance, a transmittance) and depth at full resolution.
// With `temporal` (the temporal accumulation's history pair) the reconstruction of a reprojected march accumulates
// its result as well where it is the march's last pass (CloudSettings::fuse_temporal): `accumulated` is then
// `temporal->next`, written, and step 3 is left out; otherwise it stays invalid.
struct MarchOutputs {
  TextureHandle color, depth;
  TextureHandle accumulated;
};
MarchOutputs add_march_passes(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                              const CloudLightOutputs& light, const Reprojection& rp, TextureHandle scene_depth,
                              VkBuffer ubo, const HistoryImports* temporal = nullptr);

// ---- cloud_resolve_passes.cpp ----
// 3. Temporal accumulation into the history; returns the accumulated colour.
TextureHandle add_temporal_pass(CloudResources& res, RenderGraph& graph, const MarchOutputs& march,
                                const HistoryImports& history, VkBuffer ubo);
// 4. The composite over the scene colour (with the 2.5D sky and the aerial froxels when given); returns `hdr`.
TextureHandle add_composite_pass(CloudResources& res, RenderGraph& graph, const CloudFrameInputs& in,
                                 const CloudLightOutputs& light, TextureHandle color, TextureHandle cloud_depth,
                                 TextureHandle scene_depth, TextureHandle hdr, VkBuffer ubo);

}  // namespace cumulo::clouds::render
