#pragma once
// The clouds' real-time frame in the engine (the wiring of cloud_renderer.h into the render graph): the
// light grid and the shadow map at Stage::BeforeScene, the voxel clouds at Stage::AfterOpaque (between sky
// and tonemap), from the frame's CloudFrame extension (frame/cloud_frame.h, extracted by
// frame/cloud_extraction.h) and the snapshot's SceneLighting; around them the frame passes
// (cloud_frame_pass.h: the 2.5D sky before the march; the bolts and the rain, the light shafts after it).
// Reads nothing of the world: what it draws is in the frame, how in CloudRenderOptions
// (cloud_render_options.h; the flags are parsed in options/cloud_options.h).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/gpu/buffer.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/render_feature.h"
#include "modules/clouds/frame/cloud_frame.h"
#include "modules/clouds/render/cloud_frame_pass.h"
#include "modules/clouds/render/cloud_growth_runtime.h"
#include "modules/clouds/render/cloud_render_options.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/render/hdr_capture.h"

namespace cumulo::clouds::render {

// Passes that draw the whole picture (clouds, terrain, sky) in place of the real-time clouds: the path
// tracer of `cumulo reference` / `cumulo fidelity` (reference/reference_tracer.h). Returns the new `hdr`.
class CloudFrameOverride {
 public:
  virtual ~CloudFrameOverride() = default;
  virtual cumulo::render::TextureHandle add_passes(cumulo::render::RenderGraph& graph,
                                                   const cumulo::render::FrameSnapshot& snapshot,
                                                   const CloudFrameInputs& in, const CloudLightOutputs& light,
                                                   cumulo::render::TextureHandle hdr, cumulo::render::TextureHandle depth) = 0;
};

class CloudFeature : public cumulo::render::RenderFeature {
 public:
  CloudRenderOptions& options() { return options_; }
  const CloudRenderOptions& options() const { return options_; }
  // The level has loaded (its Cloudscapes' assets resolved): the noise it needs, and what the frame passes
  // need to know of it (the 2.5D sky: --cloud-sky auto draws it with a WeatherScheduler). Before create_gpu.
  void on_level_loaded(bool has_cloudscapes, bool has_weather_scheduler, bool has_orographic_clouds = false);

  void create_gpu(cumulo::render::GpuServices& g) override;
  void destroy_gpu() override;
  void add_passes(cumulo::render::Stage stage, cumulo::render::StageContext& f) override;

  // For `cumulo bench` and tests: the renderer state (null before create_gpu), GPU bytes of the loaded
  // assets, and the mean march steps per pixel of the last completed frame (measure_steps on: a
  // side-effect pass copies the cloud depth target, whose y is the step count, to a host buffer).
  const CloudResources* resources() const { return resources_.get(); }
  uint64_t asset_gpu_bytes() const;
  CloudAssetCache* asset_cache() { return cache_.get(); }
  // A growing cloud's runtime (CloudGrowthFrame::key; null before its first frame): for tests and the bench.
  const CloudGrowthRuntime* growth_runtime(uint64_t key) const { return growth_ ? growth_->find(key) : nullptr; }
  CloudGrowthRuntime* growth_runtime(uint64_t key) { return growth_ ? growth_->find(key) : nullptr; }
  // The renderer's pipeline library (after create_gpu): passes added from outside share its hot reload.
  gpu::PipelineLibrary& pipeline_library();
  void set_measure_steps(bool on) { measure_steps_ = on; }
  // `cumulo reference` / `cumulo fidelity`: the path tracer replaces the cloud passes (and draws the terrain
  // and the sky too) while set; null: the real-time passes. Not owned.
  void set_reference(CloudFrameOverride* tracer) { reference_ = tracer; }
  // A pass drawn after the registered frame passes (cloud_frame_pass.h); before create_gpu.
  void add_frame_pass(std::unique_ptr<CloudFramePass> pass) { frame_passes_.push_back(std::move(pass)); }
  // A copy of the scene colour after the module's last pass of each frame (null: none). Not owned.
  void set_hdr_capture(HdrCapture* capture) { hdr_capture_ = capture; }
  // The next frame starts afresh: no temporal history, the light grid rebuilt whole (a new view or scene).
  void restart_history() { restart_ = true; }
  double read_steps_per_pixel() const;  // call once the frame has completed
  static constexpr const char* kStepsReadbackPass = "clouds.steps_readback";

 private:
  // `size`: the march's (dynamic resolution), what `depth` holds.
  void add_steps_readback(cumulo::render::StageContext& f, cumulo::render::TextureHandle depth, VkExtent2D size);
  // This frame's inputs from the snapshot (once per frame, at Stage::BeforeScene: the camera-cut state).
  CloudFrameInputs frame_inputs(const cumulo::render::StageContext& f, const CloudFrame& frame);
  std::shared_ptr<const CloudAsset> asset_within_budget(const std::filesystem::path& folder, const CloudFormats& formats);
  // Between the stages of one frame: its inputs and light passes (handles of that frame's graph).
  std::optional<CloudFrameInputs> inputs_;
  CloudLightOutputs light_;
  CloudRenderOptions options_;
  std::filesystem::path noise_file_;
  gpu::Context* ctx_ = nullptr;
  gpu::PipelineLibrary* library_ = nullptr;
  std::unique_ptr<CloudAssetCache> cache_;
  std::unique_ptr<CloudGrowthRuntimes> growth_;  // the growing clouds (cloud_growth_runtime.h)
  std::vector<CloudGrowthWork> growth_work_;     // this frame's, planned by frame_inputs
  CloudResourcesPtr resources_;
  std::vector<std::unique_ptr<CloudFramePass>> frame_passes_ = make_cloud_frame_passes();
  std::vector<CloudFramePass*> drawn_passes_;  // those created for this run, in order
  CloudLevelFacts level_;  // set at on_level_loaded
  glm::vec3 last_camera_{0.0f};
  std::string last_camera_name_;
  bool have_last_camera_ = false;
  bool measure_steps_ = false;
  CloudFrameOverride* reference_ = nullptr;
  bool restart_ = false;
  // Assets the GPU memory budget could not hold (gpu/gpu_budget.h): not drawn, said once, never retried.
  std::vector<std::filesystem::path> over_budget_;
  HdrCapture* hdr_capture_ = nullptr;
  gpu::Buffer steps_buffer_;
  uint64_t steps_pixels_ = 0;
};

}  // namespace cumulo::clouds::render
