#pragma once
// A cloud grown during play (issue 26), on the renderer's side: gameplay::CloudGrowth says when and how far the
// simulation runs (CloudGrowthFrame: its spec, target steps and generation); the renderer owns the simulation's GPU
// state and its images, steps it toward the target and draws it in place of the Cloudscape's folder.
//
//   CloudGrowthRuntimes growth(ctx, library);                 // one per CloudFeature (level lifetime)
//   CloudGrowthRuntime& g = growth.runtime(*instance.growth);  // one per growing cloud (CloudGrowthFrame::key)
//   CloudGrowthRuntime::Plan plan = g.plan(*instance.growth, options.growth_steps_per_frame, true, slot, 8);
//   ci.asset = g.asset();  ci.asset_grew = plan.update;       // the instance draws the grown images
//   add_cloud_growth_passes(graph, {{&g, plan}});             // before the light passes
//
// Index:  CloudGrowthRuntime  CloudGrowthRuntimes  CloudGrowthWork  add_cloud_growth_passes
//
// The images are shared, not copied: GpuGrownAsset owns the modeling (RGBA8) and field (R16) images and the runtime's
// CloudAsset borrows them (CloudAsset::borrowed; the renderer reads every asset's images through its accessors), in
// the uncompressed formats, with the grown grid's dims, voxel size and box in the cloud's local frame (x/z centred on
// the solver's box, y = 0 at its floor; the instance's Transform places it). The asset's pointer stays the same for
// the runtime's life: an instance's light grid is keyed by it, and rebuilt by CloudInstance::asset_changed instead.
//
// Synchronization: the images are imported into the render graph by the light passes as sampled (SHADER_READ_ONLY
// at the frame's start and end). The growth passes come first in the graph (declaration order is execution order)
// and GpuGrownAsset::record_update brackets its writes with full barriers (ALL_COMMANDS -> ALL_COMMANDS, layout
// SHADER_READ_ONLY -> GENERAL -> SHADER_READ_ONLY): the first orders them after every earlier read, this frame's and
// the frames' still in flight (earlier submissions on the one queue), the last makes them visible to every later
// read. The solver's buffers are read by nothing outside the growth passes. A restart (a new generation) uploads
// from the host and waits for the GPU first.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "engine/gpu/buffer.h"
#include "engine/render/graph/render_graph.h"
#include "modules/clouds/bake/grow/grow_spec.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/grow_gpu/grown_asset_gpu.h"
#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::gpu {
class Context;
class GpuTimer;
class PipelineLibrary;
}  // namespace cumulo::gpu
namespace cumulo::clouds::grow_gpu {
class GpuCloudSolver;
}  // namespace cumulo::clouds::grow_gpu

namespace cumulo::clouds::render {

class CloudGrowthRuntime {
 public:
  // Loads the spec (throws naming it), builds the simulation at its first step on the GPU and the images (no cloud
  // until the first update).
  CloudGrowthRuntime(gpu::Context& ctx, gpu::PipelineLibrary& library, const std::filesystem::path& spec,
                     float voxel = 8.0f);
  ~CloudGrowthRuntime();
  CloudGrowthRuntime(const CloudGrowthRuntime&) = delete;
  CloudGrowthRuntime& operator=(const CloudGrowthRuntime&) = delete;

  // This frame's work toward `frame`: a new generation starts again from the first step (now: waits for the GPU);
  // then up to `max_steps` steps toward target_steps (never back: a lower target holds), and an update of the images
  // after any step (or after a restart). `spread`: the images are updated in the frames after the steps, never in
  // the same one (a frame pays for the simulation or for the images and light grid, not both), over `update_frames`
  // frames (GpuGrownAsset::update_chunks: the distance field's and the attributes' passes in the first ones, the
  // images and the light grid in the last), with no step until the update is done; else all in the steps' frame.
  struct Plan {
    int steps = 0;
    grow_gpu::GrownUpdateChunk update_stages;  // the update's stages this frame records (count 0: none)
    bool update = false;     // the images change this frame (the update's last stages)
    bool first_images = false;  // ... and they are this generation's first (its light grid is built whole)
    int readback_slot = -1;  // the update's modeling image is copied for the host into this frame slot's buffer
  };
  // `slot`: the frame slot this frame records in (its previous submission complete): the modeling image copied in
  // that slot's last frame becomes the host's copy (modeling_readback). -1: no read-backs.
  Plan plan(const CloudGrowthFrame& frame, int max_steps, bool spread = true, int slot = -1, int update_frames = 1);
  // What the passes record (in the frame's command buffer, before anything samples the images).
  void record_steps(VkCommandBuffer cmd, int steps);
  // The update's stages `run` (Plan::update_stages; {0, INT32_MAX}: all of them). With a timer: the update's stages
  // as ranges (`cumulo bench` times the apart order).
  void record_update(VkCommandBuffer cmd, grow_gpu::GrownUpdateChunk run, gpu::GpuTimer* timer = nullptr,
                     grow_gpu::GrownUpdateOrder order = grow_gpu::GrownUpdateOrder::Interleaved, int readback_slot = -1);
  bool updating() const { return next_chunk_ >= 0; }  // an update spread over frames is under way

  // The host's copy of the modeling image (the march's profile, detail type, density scale and coverage, as a
  // baked modeling NVDF in the cloud's local frame) for the CPU density query (scene/density_query.h): the last
  // update whose frame has completed, a frame slot or two behind the GPU, so at most a step late when the
  // cloud grows at a step every other frame. Null until the first arrives.
  const Volume* modeling_readback() const { return readback_step_ < 0 ? nullptr : &readback_; }
  int modeling_readback_step() const { return readback_step_; }  // the solver's step it shows (-1: none yet)

  std::shared_ptr<const CloudAsset> asset() const { return asset_; }
  const grow::GrowSpec& spec() const { return spec_; }
  const std::filesystem::path& spec_file() const { return spec_file_; }
  float voxel() const { return voxel_; }
  const grow_gpu::GpuCloudSolver& solver() const { return *solver_; }
  const grow_gpu::GpuGrownAsset& grown() const { return *grown_; }
  int steps_done() const;  // recorded since the last (re)start
  // After this frame's plan: the images it draws hold no cloud (none drawn yet in this generation, or the first
  // step's state and that state has no cloud water above the iso). The renderer leaves such a cloud out of the frame's
  // instances, so a storm waiting for its event costs the march nothing (and, with a cloudless start, no update); the
  // frame that first shows cloud updates the images (Plan::first_images), so its light grid is rebuilt
  // (CloudInstance::asset_changed) as it joins; later images are swept in (asset_grew) or rebuild it.
  bool images_cloudless() const { return shown_step_ < 0 || (shown_step_ == 0 && start_cloudless_); }
  uint32_t generation() const { return generation_; }
  int restarts() const { return restarts_; }  // new generations seen (the first start not counted)

 private:
  void restart();  // the simulation back at its first step (the GPU must be idle)

  gpu::Context& ctx_;
  std::filesystem::path spec_file_;
  grow::GrowSpec spec_;
  float voxel_ = 8.0f;
  std::unique_ptr<grow_gpu::GpuCloudSolver> solver_;
  std::unique_ptr<grow_gpu::GpuGrownAsset> grown_;
  std::shared_ptr<CloudAsset> asset_;
  uint32_t generation_ = 0;
  bool started_ = false;
  bool dirty_ = true;  // the images do not show the solver's state yet
  bool stepped_last_ = false;  // the last plan stepped
  std::vector<grow_gpu::GrownUpdateChunk> chunks_;  // the update under way, a run a frame
  int next_chunk_ = -1;                             // its next run (-1: none under way)
  int shown_step_ = -1;          // the solver's step the images show after this frame's update (-1: none yet)
  bool start_cloudless_ = true;  // the first step's state has no cloud water above the iso
  struct SlotCopy {
    gpu::Buffer buffer;  // host-readable, the modeling image's bytes
    int step = -1;       // the solver's step copied into it, not yet taken (-1: none)
    uint32_t generation = 0;
  };
  std::vector<SlotCopy> slot_copies_;
  Volume readback_;
  int readback_step_ = -1;
  int restarts_ = 0;
};

// The level's growing clouds, by CloudGrowthFrame::key (they live as long as the renderer's GPU objects).
class CloudGrowthRuntimes {
 public:
  CloudGrowthRuntimes(gpu::Context& ctx, gpu::PipelineLibrary& library) : ctx_(ctx), library_(library) {}
  ~CloudGrowthRuntimes();
  // The cloud's runtime: made on first sight, made anew when its spec file or voxel changed (waits for the GPU).
  CloudGrowthRuntime& runtime(const CloudGrowthFrame& g);
  const CloudGrowthRuntime* find(uint64_t key) const;
  CloudGrowthRuntime* find(uint64_t key);
  size_t size() const { return runtimes_.size(); }

 private:
  gpu::Context& ctx_;
  gpu::PipelineLibrary& library_;
  std::map<uint64_t, std::unique_ptr<CloudGrowthRuntime>> runtimes_;
};

// One growing cloud's work this frame.
struct CloudGrowthWork {
  CloudGrowthRuntime* runtime = nullptr;
  CloudGrowthRuntime::Plan plan;
};
// The side-effect passes "clouds.grow" (the steps) and "clouds.grow_asset" (the images from the new state), added
// for every growing cloud of the frame even with no work (one graph shape whether the clouds grow or hold). Declare
// them before the light passes, which import the images.
inline constexpr const char* kGrowPass = "clouds.grow";
inline constexpr const char* kGrowAssetPass = "clouds.grow_asset";
void add_cloud_growth_passes(cumulo::render::RenderGraph& graph, const std::vector<CloudGrowthWork>& work);

}  // namespace cumulo::clouds::render
