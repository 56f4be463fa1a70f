#include "modules/clouds/render/cloud_feature.h"

#include "engine/render/pass_helpers.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/gpu_budget.h"
#include "engine/core/log.h"
#include "engine/render/budget_mode.h"
#include "modules/clouds/scene/cloudscape_assets.h"

namespace cumulo::clouds::render {
namespace fs = std::filesystem;
namespace {

// A camera that jumps further than this in one frame (a cut, a teleport) invalidates the history.
constexpr float kCameraCutMetres = 200.0f;

}  // namespace

void CloudFeature::on_level_loaded(bool has_cloudscapes, bool has_weather_scheduler, bool has_orographic_clouds) {
  // The renderer's resources (its composite) serve the 2.5D sky and the envelope clouds too: a level with either and no
  // cloudscape still gets them.
  if ((has_cloudscapes || has_weather_scheduler || has_orographic_clouds) && noise_file_.empty())
    noise_file_ = prepare_voxel_noise(options_.noise_size);
  level_.has_weather_scheduler = has_weather_scheduler;
  level_.has_orographic_clouds = has_orographic_clouds;
}

void CloudFeature::create_gpu(cumulo::render::GpuServices& g) {
  ctx_ = &g.ctx;
  library_ = &g.library;
  cache_ = std::make_unique<CloudAssetCache>(g.ctx);
  growth_ = std::make_unique<CloudGrowthRuntimes>(g.ctx, g.library);
  if (noise_file_.empty()) return;  // the level has no clouds
  // The talk's 256x256x32 grid, or on CPU devices a smaller one (its eighth per frame would cost about
  // as much as the whole march there) unless --cloud-light-grid talk asks for the talk's.
  CloudResourcesDesc desc = options_.talk_light_grid.value_or(false) ? CloudResourcesDesc{}
                                                                     : CloudResourcesDesc::for_device(g.ctx.info());
  if (options_.light_grid_samples > 0) desc.light_grid_sweep_samples = options_.light_grid_samples;
  resources_ = create_cloud_resources(g.ctx, g.library, cache_->noise(noise_file_), desc);
  drawn_passes_.clear();
  for (const auto& p : frame_passes_)
    if (p->create_gpu(g, options_, level_)) drawn_passes_.push_back(p.get());
}

void CloudFeature::destroy_gpu() {
  // A frame that threw between its stages (a shader missing at run time) leaves its inputs here: they hold the
  // assets' GPU images, which must go before the device does.
  inputs_.reset();
  light_ = {};
  steps_buffer_.reset();
  steps_pixels_ = 0;
  for (CloudFramePass* p : drawn_passes_) p->destroy_gpu();
  drawn_passes_.clear();
  growth_work_.clear();
  resources_.reset();
  growth_.reset();
  cache_.reset();
  ctx_ = nullptr;
  library_ = nullptr;
}

gpu::PipelineLibrary& CloudFeature::pipeline_library() {
  if (!library_) fail("clouds: the feature's GPU objects are not created yet");
  return *library_;
}

uint64_t CloudFeature::asset_gpu_bytes() const { return cache_ ? cache_->gpu_bytes() : 0; }

// An asset the GPU memory budget cannot hold is not drawn: the level goes on without it, and says so once (the
// instances of one frame share one format set, so a compressed fallback for one asset alone is not an option).
std::shared_ptr<const CloudAsset> CloudFeature::asset_within_budget(const std::filesystem::path& folder,
                                                                    const CloudFormats& formats) {
  for (const std::filesystem::path& f : over_budget_)
    if (f == folder) return nullptr;
  try {
    return cache_->cloudscape(folder, formats);
  } catch (const gpu::GpuBudgetError& e) {
    LOG_WARN("clouds: %s: not drawn: %s", folder.string().c_str(), e.what());
    over_budget_.push_back(folder);
    return nullptr;
  }
}

CloudFrameInputs CloudFeature::frame_inputs(const cumulo::render::StageContext& f, const CloudFrame& frame) {
  const cumulo::render::FrameSnapshot& s = f.snapshot;
  // A grown cloud's images are uncompressed (grown_asset_gpu.h) and the instances of one frame share one format set:
  // a frame with one draws every cloudscape uncompressed (unless --cloud-formats says otherwise, which import_cloud_assets
  // then refuses, naming both).
  const bool growing = std::any_of(frame.instances.begin(), frame.instances.end(),
                                   [](const CloudInstanceFrame& i) { return i.growth.has_value(); });
  const CloudFormats formats = CloudFormats::from_set(
      options_.formats.value_or(growing ? CloudFormatSet::Uncompressed : default_format_set(ctx_->info())));
  CloudSettings settings = cloud_settings(options_);
  settings.split_distance_m = split_distance_for_device(options_, ctx_->info().is_cpu());
  // Camera, time, budget mode, the sun (pi x the engine's Lambertian radiance) and the sky's ambient.
  CloudFrameInputs in = cloud_inputs_from_snapshot(s, f.slot, settings);
  growth_work_.clear();
  for (uint32_t k = 0; k < frame.instances.size(); ++k) {
    const CloudInstanceFrame& i = frame.instances[k];
    CloudInstance ci;
    static_cast<CloudPlacement&>(ci) = i;
    if (i.growth) {
      // Drawn from its simulation's images (stepped by this frame's growth passes), not the folder's asset. One the
      // GPU memory budget cannot hold is not drawn, as an asset (said once, never retried).
      if (std::find(over_budget_.begin(), over_budget_.end(), i.growth->spec) != over_budget_.end()) continue;
      CloudGrowthRuntime* g = nullptr;
      try {
        g = &growth_->runtime(*i.growth);
      } catch (const gpu::GpuBudgetError& e) {
        LOG_WARN("clouds: %s: not grown: %s", i.growth->spec.string().c_str(), e.what());
        over_budget_.push_back(i.growth->spec);
        continue;
      }
      const CloudGrowthRuntime::Plan plan = g->plan(*i.growth, options_.growth_steps_per_frame, options_.growth_spread,
                                                          int(f.slot),
                                                          growth_update_frames_for_device(options_, ctx_->info().is_cpu()));
      growth_work_.push_back({g, plan});
      if (g->images_cloudless()) continue;  // still stepped; not marched, lit or traced until it shows a cloud
      ci.asset = g->asset();
      // A generation's first images rebuild the grid (it may hold the last generation's cloud), later ones are swept in.
      (options_.growth_light_sweep && !plan.first_images ? ci.asset_grew : ci.asset_changed) = plan.update;
    } else {
      ci.asset = asset_within_budget(i.folder, formats);
    }
    if (!ci.asset) continue;
    in.instances.push_back(std::move(ci));
    in.frame_instances.push_back(k);
  }
  in.lights = frame.lights;
  in.terrain_depth = f.light_depth.texture;
  in.terrain_depth_matrix = f.light_depth.world_to_light;
  in.terrain_depth_range_m = f.light_depth.depth_range_m;
  // The weather drawn this frame (its instances' share is in frame.instances already).
  if (const std::optional<CloudWeatherLighting>& w = frame.weather_lighting) {
    in.settings.extinction = w->extinction;
    in.settings.hg_forward = w->hg_forward;
    in.settings.hg_backward = w->hg_backward;
    in.settings.hg_forward_weight = w->hg_forward_weight;
    in.ambient_color *= w->ambient;
  }
  const bool cut = have_last_camera_ && (s.camera_name != last_camera_name_ ||
                                         glm::length(s.camera.position - last_camera_) > kCameraCutMetres);
  in.camera_cut = cut || restart_;
  in.rebuild_light_grid = restart_;
  restart_ = false;
  last_camera_ = s.camera.position;
  last_camera_name_ = s.camera_name;
  have_last_camera_ = true;
  return in;
}

void CloudFeature::add_passes(cumulo::render::Stage stage, cumulo::render::StageContext& f) {
  using cumulo::render::Stage;
  if (stage == Stage::AfterTonemap || !options_.enabled || !resources_) return;
  const CloudFrame* frame = f.snapshot.extensions.find<CloudFrame>();
  // Without voxel instances the 2.5D sky and the envelope clouds still draw (the renderer composites them alone).
  if (!frame) return;
  // Before the scene: the light grid and the shadow map (the geometry reads it); after it, the rest.
  if (stage == Stage::BeforeScene) {
    inputs_ = frame_inputs(f, *frame);
    // The growing clouds' steps and images first: the light passes import the images (cloud_growth_runtime.h).
    add_cloud_growth_passes(f.graph, growth_work_);
    growth_work_.clear();
    light_ = add_cloud_light_passes(*resources_, f.graph, *inputs_);
    inputs_->voxel_shadow = light_.shadow;
    cumulo::render::LightShadowMap shadow = light_.shadow;
    for (CloudFramePass* p : drawn_passes_) p->add_before_scene(f, *frame, *inputs_, shadow);
    if (shadow.texture.valid()) f.resources.publish(shadow);
    return;
  }
  if (!inputs_) return;  // (a renderer always runs BeforeScene first)
  CloudFrameInputs in = std::move(*inputs_);
  inputs_.reset();
  if (const auto* aerial = f.resources.find<cumulo::render::AerialPerspective>()) in.aerial = aerial->froxels;
  if (reference_) {
    // The path tracer draws the whole picture (clouds, terrain, sky) in place of the real-time passes.
    for (CloudFramePass* p : drawn_passes_) p->add_before_reference(f, *frame, in);
    f.hdr = reference_->add_passes(f.graph, f.snapshot, in, light_, f.hdr, f.depth);
    light_ = {};
    if (hdr_capture_) hdr_capture_->add_pass(f.graph, f.hdr);
    return;
  }
  for (CloudFramePass* p : drawn_passes_) p->add_before_clouds(f, *frame, in);
  CloudPassOutputs outputs;
  // The passes' additions before the composite go to the composite's copy of the inputs and to `in` (the passes after
  // the clouds read them: the light shafts the 2.5D sky).
  const BeforeComposite before_composite = [&](const CloudPassOutputs& voxel, CloudFrameInputs& composite_in) {
    for (CloudFramePass* p : drawn_passes_) p->add_before_composite(f, *frame, voxel, composite_in);
    in.sky_color = composite_in.sky_color;
    in.sky_depth = composite_in.sky_depth;
    in.envelope_color = composite_in.envelope_color;
    in.envelope_depth = composite_in.envelope_depth;
    in.envelope_upsample = composite_in.envelope_upsample;
  };
  f.hdr = add_cloud_passes(*resources_, f.graph, in, f.hdr, f.depth, &outputs, &light_, before_composite);
  light_ = {};
  if (measure_steps_ && outputs.depth.valid())
    add_steps_readback(f, outputs.depth, cumulo::render::relative_extent(f.graph.output_size(), in.resolution_scale));
  const CloudFramePassContext context{f, *frame, in, outputs};
  for (CloudFramePass* p : drawn_passes_) f.hdr = p->add_passes(context);
  if (hdr_capture_) hdr_capture_->add_pass(f.graph, f.hdr);
}

void CloudFeature::add_steps_readback(cumulo::render::StageContext& f, cumulo::render::TextureHandle depth,
                                      VkExtent2D size) {
  using namespace cumulo::render;
  const uint64_t pixels = uint64_t(size.width) * size.height;
  if (!steps_buffer_ || steps_pixels_ != pixels) {
    if (steps_buffer_) ctx_->wait_idle();
    steps_buffer_ = gpu::Buffer(*ctx_, {pixels * sizeof(glm::vec4), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        gpu::MemoryUsage::Readback, "clouds steps readback"});
    steps_pixels_ = pixels;
  }
  add_readback_pass(f.graph, kStepsReadbackPass, {{depth, steps_buffer_.handle()}}, steps_buffer_.size());
}

double CloudFeature::read_steps_per_pixel() const {
  if (!steps_buffer_ || steps_pixels_ == 0) return 0.0;
  std::vector<glm::vec4> px(steps_pixels_);
  steps_buffer_.download(px.data(), px.size() * sizeof(glm::vec4));
  double sum = 0;
  for (const glm::vec4& p : px) sum += p.y;
  return sum / double(px.size());
}

}  // namespace cumulo::clouds::render
