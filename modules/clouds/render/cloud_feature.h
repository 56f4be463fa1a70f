#pragma once
// The clouds module's runtime (the wiring of cloud_renderer.h into the engine): `cumulo run` flags,
// the Cloudscape assets of a level, the per-frame CloudFrame extension, and the cloud passes at the
// AfterOpaque stage (between sky and tonemap), using the sun and ambient colours of the snapshot's
// SceneLighting (the atmosphere replaces those later); then the lightning bolts and the rain
// (cloud_effects.h), and the ground discharges' light on the terrain (SceneLighting::point_lights).
//
//   --clouds on|off            off: the same frame without the module's passes
//   --cloud-debug VIEW         none | profile | steps | light-grid | split
//   --cloud-formats SET        compressed | uncompressed (default: by device type)
//   --cloud-ablation A         base | voxel-lighting | full (the talk's cost table; default full)
//   --cloud-temporal on|off    temporal accumulation of the jittered march (default on)
//   --cloud-reprojection N     1 of N pixels per frame of the full-resolution march with temporal on: 1 (every
//                              pixel, the 2023 talk), 4, 16 (the 2015 talk), auto (default: 4 at 30 Hz, 16 for
//                              the 40/60 Hz far segment)
//   --cloud-light-grid talk|device   the talk's 256x256x32 light grid, or one sized for the device
//                              (default: 96x96x16 on CPU devices, the talk's elsewhere)
//   --cloud-shadows on|off     the clouds' shadow on the terrain and the ocean (default on)
//   --cloud-terrain-shadow on|off  the terrain's shadow on the clouds (the key light's depth map; default on)
//   --cloud-light-shafts on|off  light shafts through gaps in the clouds (light_shafts.h; default on)
//   --cloud-rain on|off        the rain columns under precipitating clouds (default on)
//   --cloud-effects-off LIST   lighting effects of the talks switched off in the march (cumulo fidelity measures each)
//   --cloud-lighting talk|tuned  the lighting constants: the talks' (default) or tuned against the reference
//   --cloud-ms-strength X, --cloud-ambient-occlusion X   override those two constants of the preset
//   --weather-dir DIR          the folder of weather states (default content/weather/)
//   --cloud-sky auto|on|off    the weather-driven 2.5D sky beyond and above the voxel cloudscape
//                              (sky_layer.h; auto, the default: on when the level has a WeatherScheduler)
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/ecs/world.h"
#include "engine/gpu/buffer.h"
#include "engine/render/frame_snapshot.h"
#include "engine/render/render_feature.h"
#include "modules/clouds/render/cloud_effects.h"
#include "modules/clouds/render/cloud_renderer.h"
#include "modules/clouds/render/hdr_capture.h"
#include "modules/clouds/render/light_shafts.h"
#include "modules/clouds/render/reference_tracer.h"
#include "modules/clouds/render/sky_layer.h"
#include "modules/clouds/weather/weather_library.h"
#include "modules/clouds/weather/weather_state.h"

namespace cumulo {
class ArgParser;
}
namespace cumulo::scene {
struct LevelInfo;
}

namespace cumulo::clouds::render {

// One Cloudscape entity, as extracted for a frame.
struct CloudInstanceFrame : CloudPlacement {
  std::filesystem::path folder;  // resolved NVDF folder
  float rain = 0.0f;             // Cloudscape "rain" (0..1), before dissipation
};

// The snapshot extension of the clouds module.
struct CloudFrame {
  std::vector<CloudInstanceFrame> instances;
  std::vector<CloudPointLight> lights;
  std::vector<BoltFrame> bolts;  // ground discharges live this frame (their visible channels)
  std::optional<weather::WeatherState> weather;  // the WeatherScheduler's blend this frame (none: no scheduler)
  SkyLayerFrame sky;  // the 2.5D sky's parameters (enabled by --cloud-sky; driven by `weather`)
};

struct CloudRunOptions {
  bool enabled = true;
  CloudDebugView debug = CloudDebugView::None;
  std::optional<CloudFormatSet> formats;  // empty: default_format_set(device)
  CloudAblation ablation = CloudAblation::Full;
  bool temporal = true;
  uint32_t reprojection_block = 0;  // CloudSettings::reprojection_block (0: by budget mode)
  bool talk_light_grid = false;  // true: 256x256x32 on every device
  CloudLightGridMethod light_grid_method = CloudLightGridMethod::Sweep;
  bool light_sample_noise_mean = true;  // CloudSettings::light_sample_noise_mean
  bool light_grid_always_update = false;  // CloudSettings::light_grid_always_update (cumulo bench)
  bool shadows = true;  // --cloud-shadows: the clouds' shadow on the terrain and the ocean
  std::optional<bool> sky;  // --cloud-sky on|off; none (auto): on when the level has a WeatherScheduler
  bool light_shafts = true;  // --cloud-light-shafts
  bool rain = true;          // --cloud-rain
  bool terrain_shadow = true;  // --cloud-terrain-shadow: the terrain's shadow on the clouds
  uint32_t effects = CLOUD_EFFECTS_ALL;  // --cloud-effects-off: CLOUD_EFFECT_* bits in effect
  CloudLightingPreset lighting = CloudLightingPreset::Slab;  // --cloud-lighting talk|tuned|diffusion|slab
  // --cloud-ms-strength / --cloud-ambient-occlusion: override the preset's value (< 0: the preset's).
  float ms_strength = -1.0f, ambient_occlusion = -1.0f;
  float ms_attenuation_inside = -1.0f;  // --cloud-ms-attenuation-inside
  float ms_other_clouds = -1.0f;        // --cloud-ms-other-clouds
  float ms_enclosed = -1.0f;            // --cloud-ms-enclosed
  float ground_albedo = -1.0f;          // --cloud-ground-albedo
  float ms_anisotropy = -1.0f;          // --cloud-ms-anisotropy
  float light_sample_m = -1.0f;         // --cloud-light-sample-m
  float edge_depth = -1.0f;             // --cloud-edge-depth
  int instance_shadows = -1;            // --cloud-instance-shadows: 1 on, 0 off, -1 the preset's
  float ms_lateral = -1.0f;             // --cloud-ms-lateral
  int sky_mean = -1;                    // --cloud-sky-mean: 1 on, 0 off, -1 the preset's
  // cumulo fidelity: draw only what the path-traced reference traces (the voxel clouds): no 2.5D sky,
  // light shafts, rain or bolt channels.
  bool reference_comparable = false;
  std::optional<weather::WeatherState> weather;  // --weather ID: applied every frame (weather_lighting.h)
  int noise_size = 128;
};

class CloudFeature : public cumulo::render::RenderFeature {
 public:
  void add_run_options(ArgParser& p);
  void check_run_options();
  CloudRunOptions& options() { return options_; }
  // The weather states, loaded when the level has a WeatherScheduler or WeatherZone (else null).
  const weather::WeatherLibrary* weather_library() const { return weather_lib_ ? &*weather_lib_ : nullptr; }
  // The editor's live edits go here (null: the level has no scheduler or zone).
  weather::WeatherLibrary* mutable_weather_library() { return weather_lib_ ? &*weather_lib_ : nullptr; }
  // The editor's preview: this state is drawn instead of the scheduler's (the simulation is unchanged).
  void set_weather_preview(std::optional<weather::WeatherState> state) { weather_preview_ = std::move(state); }
  const std::optional<weather::WeatherState>& weather_preview() const { return weather_preview_; }
  // --weather-dir, else content/weather/.
  std::filesystem::path weather_folder() const;
  const SkyLayer* sky_layer() const { return sky_.get(); }

  // Resolves every Cloudscape's asset (bakes recipes into the cache) and the noise. Throws naming the
  // level file and entity for a bad asset or a non-uniform scale.
  void on_level_loaded(ecs::World& world, const scene::LevelInfo& level);
  void extract(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) const;

  void create_gpu(cumulo::render::GpuServices& g) override;
  void destroy_gpu() override;
  void add_passes(cumulo::render::Stage stage, cumulo::render::StageContext& f) override;

  // For `cumulo bench` and tests: the renderer state (null before create_gpu), GPU bytes of the loaded
  // assets, and the mean march steps per pixel of the last completed frame (measure_steps on: a
  // side-effect pass copies the cloud depth target, whose y is the step count, to a host buffer).
  const CloudResources* resources() const { return resources_.get(); }
  uint64_t asset_gpu_bytes() const;
  CloudAssetCache* asset_cache() { return cache_.get(); }
  // The renderer's pipeline library (after create_gpu): passes added from outside share its hot reload.
  gpu::PipelineLibrary& pipeline_library();
  void set_measure_steps(bool on) { measure_steps_ = on; }
  // `cumulo reference` / `cumulo fidelity`: the path tracer replaces the cloud passes (and draws the terrain
  // and the sky too) while set; null: the real-time passes. Not owned.
  void set_reference(ReferenceTracer* tracer) { reference_ = tracer; }
  // A copy of the scene colour after the module's last pass of each frame (null: none). Not owned.
  void set_hdr_capture(HdrCapture* capture) { hdr_capture_ = capture; }
  // The next frame starts afresh: no temporal history, the light grid rebuilt whole (a new view or scene).
  void restart_history() { restart_ = true; }
  double read_steps_per_pixel() const;  // call once the frame has completed
  static constexpr const char* kStepsReadbackPass = "clouds.steps_readback";

 private:
  void add_steps_readback(cumulo::render::StageContext& f, cumulo::render::TextureHandle depth);
  // This frame's inputs from the snapshot (once per frame, at Stage::BeforeScene: the camera-cut state).
  CloudFrameInputs frame_inputs(const cumulo::render::StageContext& f, const CloudFrame& frame);
  // Between the stages of one frame: its inputs and light passes (handles of that frame's graph).
  std::optional<CloudFrameInputs> inputs_;
  CloudLightOutputs light_;
  CloudRunOptions options_;
  std::optional<weather::WeatherLibrary> weather_lib_;  // loaded when the level has a WeatherScheduler
  std::optional<weather::WeatherState> weather_preview_;
  std::string debug_text_, formats_text_, ablation_text_, clouds_text_ = "on", temporal_text_ = "on",
      light_grid_text_ = "device", reprojection_text_ = "auto", light_grid_method_text_ = "sweep",
      light_noise_text_ = "mean", weather_text_, shadows_text_ = "on", sky_text_ = "auto",
      shafts_text_ = "on", rain_text_ = "on", terrain_shadow_text_ = "on", effects_off_text_, lighting_text_ = "slab", weather_dir_text_,
      instance_shadows_text_ = "preset", sky_mean_text_ = "preset";
  std::filesystem::path noise_file_;
  gpu::Context* ctx_ = nullptr;
  gpu::PipelineLibrary* library_ = nullptr;
  std::unique_ptr<CloudAssetCache> cache_;
  CloudResourcesPtr resources_;
  std::unique_ptr<CloudEffects> effects_;
  std::unique_ptr<SkyLayer> sky_;
  std::unique_ptr<LightShafts> shafts_;
  bool sky_enabled_ = false;  // resolved at on_level_loaded
  glm::vec3 last_camera_{0.0f};
  std::string last_camera_name_;
  bool have_last_camera_ = false;
  bool measure_steps_ = false;
  ReferenceTracer* reference_ = nullptr;
  bool restart_ = false;
  HdrCapture* hdr_capture_ = nullptr;
  gpu::Buffer steps_buffer_;
  uint64_t steps_pixels_ = 0;
};

}  // namespace cumulo::clouds::render
