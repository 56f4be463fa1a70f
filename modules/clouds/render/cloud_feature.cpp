#include "modules/clouds/render/cloud_feature.h"

#include "engine/render/pass_helpers.h"

#include <algorithm>
#include <cmath>

#include "engine/core/args.h"
#include "engine/core/error.h"
#include "engine/ecs/world.h"
#include "engine/gpu/context.h"
#include "engine/render/budget_mode.h"
#include "engine/scene/components.h"
#include "engine/scene/level.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/scene/cloudscape_assets.h"
#include "modules/clouds/render/weather_lighting.h"
#include "modules/clouds/weather/weather_library.h"
#include "modules/clouds/weather/weather_scheduler.h"
#include "modules/clouds/weather/weather_zone.h"
#include "modules/clouds/gameplay/lightning.h"
#include "modules/clouds/gameplay/triggers.h"

namespace cumulo::clouds::render {
namespace fs = std::filesystem;
namespace {

bool parse_on_off(const std::string& flag, const std::string& text) {
  if (text == "on") return true;
  if (text == "off") return false;
  fail("%s: expected on or off, got \"%s\"", flag.c_str(), text.c_str());
}
// on|off|preset: 1, 0, or -1 (the lighting preset decides).
int parse_on_off_preset(const std::string& flag, const std::string& text) {
  if (text == "preset") return -1;
  if (text == "on") return 1;
  if (text == "off") return 0;
  fail("%s: expected on, off or preset, got \"%s\"", flag.c_str(), text.c_str());
}

// A camera that jumps further than this in one frame (a cut, a teleport) invalidates the history.
constexpr float kCameraCutMetres = 200.0f;

}  // namespace

void CloudFeature::add_run_options(ArgParser& p) {
  p.option("--clouds", "on|off", "draw the cloud module's passes (default on)", &clouds_text_)
      .option("--cloud-debug", "VIEW", "cloud debug view: none, profile, steps, light-grid, split", &debug_text_)
      .option("--cloud-formats", "SET", "cloud GPU formats: compressed (BC1) or uncompressed (RGBA8 + R16); default by device",
              &formats_text_)
      .option("--cloud-ablation", "A", "cloud march variant of the talk's cost table: base, voxel-lighting, full (default)",
              &ablation_text_)
      .option("--cloud-temporal", "on|off", "temporal accumulation of the jittered cloud march (default on)", &temporal_text_)
      .option("--cloud-reprojection", "auto|1|4|16",
              "march 1 of N pixels per frame and reproject the rest (with temporal on): 1 every pixel, 4, 16 as in "
              "the 2015 talk, auto (default: 4 at 30 Hz, 16 for the 40/60 Hz far segment)",
              &reprojection_text_)
      .option("--cloud-light-grid", "talk|device",
              "light grid size: the talk's 256x256x32, or sized for the device (default: 96x96x16 on CPU devices)",
              &light_grid_text_)
      .option("--cloud-light-grid-method", "rays|sweep",
              "light grid computation: the talk's ray from every voxel, or a sweep level by level from the light "
              "(default; the same sums at a fraction of the cost)",
              &light_grid_method_text_)
      .option("--cloud-light-sample-noise", "mean|sampled",
              "noise in the two marched light samples: its mean (default), or sampled as in the talk", &light_noise_text_)
      .option("--cloud-shadows", "on|off", "the clouds' shadow on the terrain and the ocean (default on)", &shadows_text_)
      .option("--cloud-terrain-shadow", "on|off", "the terrain's shadow on the clouds (default on)", &terrain_shadow_text_)
      .option("--cloud-light-shafts", "on|off", "light shafts through gaps in the clouds (default on)", &shafts_text_)
      .option("--cloud-rain", "on|off", "the rain columns under precipitating clouds (default on)", &rain_text_)
      .option("--cloud-sky", "auto|on|off",
              "the weather-driven 2.5D sky beyond and above the voxel cloudscape (default auto: on with a WeatherScheduler)",
              &sky_text_)
      .option("--cloud-effects-off", "LIST",
              "switch off lighting effects of the talks in the march, comma-separated: silver-lining, dark-edges, "
              "inner-glow, long-shadows, ambient-direction, lightning-glow (default: all on)",
              &effects_off_text_)
      .option("--cloud-lighting", "talk|tuned|diffusion|slab",
              "the lighting model: the talks' constants, the set tuned against the path-traced reference "
              "(cumulo fidelity), diffusion's falloff of the multiple scattering through a cloud and Beer-Lambert "
              "across other clouds, or the slab (default; issue 21): a slab's falloff from the cloud's depth on both "
              "sides along the sun's line, enclosed air (a chamber) inside the cloud, the sky from the upper "
              "hemisphere, its diffused light, a ground bounce and a forward lobe of the multiple scattering",
              &lighting_text_)
      .option("--cloud-ms-strength", "X", "the multiple-scattering field's strength, overriding the preset's (talk: 1)",
              &options_.ms_strength)
      .range(0.0, 100.0)
      .option("--cloud-ambient-occlusion", "X",
              "the scale of the summed sky density on the ambient, overriding the preset's (talk: 0.1)",
              &options_.ambient_occlusion)
      .range(0.0, 100.0)
      .option("--cloud-ms-attenuation-inside", "X",
              "the multiple-scattering field's attenuation deep inside a cloud toward the sun (the inner glow's "
              "relaxation), overriding the preset's (talk: 0.05)",
              &options_.ms_attenuation_inside)
      .range(0.0, 10.0)
      .option("--cloud-ms-other-clouds", "X",
              "with the diffusion lighting, the Beer-Lambert coefficient of other clouds' optical depth on the multiple "
              "scattering, overriding the preset's (diffusion: 1; 0: other clouds shadow it as its own cloud does)",
              &options_.ms_other_clouds)
      .range(0.0, 10.0)
      .option("--cloud-ms-enclosed", "X",
              "with the diffusion lighting, the own cloud goes on across air under at least this sky optical depth (a "
              "chamber inside a cloud), overriding the preset's (slab: 3; 0: it ends at the first air toward the sun)",
              &options_.ms_enclosed)
      .range(0.0, 1000.0)
      .option("--cloud-ground-albedo", "X",
              "with the slab lighting, the ground's albedo for the light it bounces into the clouds' bases, overriding "
              "the preset's (slab: 0.1; 0: no bounce)",
              &options_.ground_albedo)
      .range(0.0, 1.0)
      .option("--cloud-light-sample-m", "M",
              "the length of each of the two marched light samples before the light grid (default 24 m)",
              &options_.light_sample_m)
      .range(1.0, 200.0)
      .option("--cloud-edge-depth", "X",
              "with the slab lighting, the dark edges from the optical depth to the nearest surface, 1 - exp(-X depth), "
              "overriding the preset's (0: the talks' profile)",
              &options_.edge_depth)
      .range(0.0, 100.0)
      .option("--cloud-instance-shadows", "on|off|preset",
              "other cloud instances' clouds shadow an instance's (the storm cloud and the cloudscape), overriding the "
              "preset's (slab: on)",
              &instance_shadows_text_)
      .option("--cloud-ms-lateral", "C",
              "with the slab lighting, the multiple scattering's leak through a surface nearer than both ends of the sun's "
              "line through the cloud, overriding the preset's (0: none)",
              &options_.ms_lateral)
      .range(0.0, 100.0)
      .option("--cloud-sky-mean", "on|off|preset",
              "the clouds' sky light from the sky's mean radiance over the upper hemisphere (on) or 0.5 (zenith + "
              "horizon) (off), overriding the preset's (slab: off)",
              &sky_mean_text_)
      .option("--cloud-ms-anisotropy", "X",
              "with the slab lighting, the multiple scattering's forward lobe near the lit surface as a fraction of the "
              "phase function's mean cosine, overriding the preset's (0: isotropic)",
              &options_.ms_anisotropy)
      .range(0.0, 2.0)
      .option("--weather", "ID", "start in this weather state of content/weather/ (clear, fair_cumulus, ...)",
              &weather_text_)
      .option("--weather-dir", "DIR", "the folder of weather states (default content/weather/; the editor saves there)",
              &weather_dir_text_);
}

std::filesystem::path CloudFeature::weather_folder() const {
  return weather_dir_text_.empty() ? weather::WeatherLibrary::default_folder() : std::filesystem::path(weather_dir_text_);
}

void CloudFeature::check_run_options() {
  options_.enabled = parse_on_off("--clouds", clouds_text_);
  options_.temporal = parse_on_off("--cloud-temporal", temporal_text_);
  options_.shadows = parse_on_off("--cloud-shadows", shadows_text_);
  options_.light_shafts = parse_on_off("--cloud-light-shafts", shafts_text_);
  options_.rain = parse_on_off("--cloud-rain", rain_text_);
  options_.terrain_shadow = parse_on_off("--cloud-terrain-shadow", terrain_shadow_text_);
  options_.instance_shadows = parse_on_off_preset("--cloud-instance-shadows", instance_shadows_text_);
  options_.sky_mean = parse_on_off_preset("--cloud-sky-mean", sky_mean_text_);
  options_.sky.reset();
  if (sky_text_ != "auto") options_.sky = parse_on_off("--cloud-sky", sky_text_);
  if (reprojection_text_ == "auto") options_.reprojection_block = 0;
  else if (reprojection_text_ == "1") options_.reprojection_block = 1;
  else if (reprojection_text_ == "4") options_.reprojection_block = 2;
  else if (reprojection_text_ == "16") options_.reprojection_block = 4;
  else fail("--cloud-reprojection: expected auto, 1, 4 or 16, got \"%s\"", reprojection_text_.c_str());
  if (light_grid_text_ != "talk" && light_grid_text_ != "device")
    fail("--cloud-light-grid: expected talk or device, got \"%s\"", light_grid_text_.c_str());
  options_.talk_light_grid = light_grid_text_ == "talk";
  if (light_noise_text_ != "mean" && light_noise_text_ != "sampled")
    fail("--cloud-light-sample-noise: expected mean or sampled, got \"%s\"", light_noise_text_.c_str());
  options_.light_sample_noise_mean = light_noise_text_ == "mean";
  options_.weather.reset();
  if (!weather_text_.empty())
    options_.weather = weather::WeatherLibrary::load(weather_folder()).get(weather_text_);
  if (!parse_light_grid_method(light_grid_method_text_, &options_.light_grid_method))
    fail("--cloud-light-grid-method: expected rays or sweep, got \"%s\"", light_grid_method_text_.c_str());
  if (!debug_text_.empty() && !parse_debug_view(debug_text_, &options_.debug))
    fail("--cloud-debug: unknown view \"%s\" (expected none, profile, steps, light-grid or split)", debug_text_.c_str());
  if (!formats_text_.empty()) {
    CloudFormatSet set;
    if (!parse_format_set(formats_text_, &set))
      fail("--cloud-formats: unknown set \"%s\" (expected compressed or uncompressed)", formats_text_.c_str());
    options_.formats = set;
  }
  if (!parse_lighting_preset(lighting_text_, &options_.lighting))
    fail("--cloud-lighting: expected talk, tuned, diffusion or slab, got \"%s\"", lighting_text_.c_str());
  options_.effects = CLOUD_EFFECTS_ALL;
  for (size_t b = 0; b < effects_off_text_.size();) {
    size_t e = effects_off_text_.find(',', b);
    if (e == std::string::npos) e = effects_off_text_.size();
    const std::string name = effects_off_text_.substr(b, e - b);
    const uint32_t bit = cloud_effect_bit(name);
    if (!name.empty() && !bit)
      fail("--cloud-effects-off: unknown effect \"%s\" (expected silver-lining, dark-edges, inner-glow, long-shadows, "
           "ambient-direction or lightning-glow)", name.c_str());
    options_.effects &= ~bit;
    b = e + 1;
  }
  if (!ablation_text_.empty() && !parse_ablation(ablation_text_, &options_.ablation))
    fail("--cloud-ablation: unknown variant \"%s\" (expected base, voxel-lighting or full)", ablation_text_.c_str());
}

void CloudFeature::on_level_loaded(ecs::World& world, const scene::LevelInfo& level) {
  bool any = false;
  world.view<Cloudscape>().each([&](ecs::Entity e, Cloudscape& c) {
    if (const auto* t = world.try_get<scene::Transform>(e)) {
      const glm::vec3 s = t->scale;
      if (std::fabs(s.x - s.y) > 1e-4f * std::fabs(s.x) || std::fabs(s.x - s.z) > 1e-4f * std::fabs(s.x) || !(s.x > 0.0f))
        fail("%s: a Cloudscape's Transform needs one positive uniform scale, got (%g, %g, %g)", c.where.c_str(), s.x, s.y,
             s.z);
    }
    fs::path p(c.asset);
    c.resolved = prepare_cloudscape_asset((p.is_absolute() ? p : level.directory / p).lexically_normal(), c.where);
    any = true;
  });
  if (any && noise_file_.empty()) noise_file_ = prepare_voxel_noise(options_.noise_size);
  // Every weather state the level names must exist; `--weather ID` is the state schedulers start in.
  auto library = [&]() -> const weather::WeatherLibrary& {
    if (!weather_lib_) weather_lib_ = weather::WeatherLibrary::load(weather_folder());
    return *weather_lib_;
  };
  auto where = [&](ecs::Entity e, const char* component) {
    const auto* n = world.try_get<ecs::Name>(e);
    return level.file.string() + ": entity \"" + (n ? n->value : "?") + "\": " + component;
  };
  bool scheduler = false;
  world.view<weather::WeatherScheduler>().each([&](ecs::Entity e, weather::WeatherScheduler& w) {
    scheduler = true;
    if (options_.weather) w.start = options_.weather->id;
    check_scheduler_states(w, library(), where(e, "WeatherScheduler"));
  });
  sky_enabled_ = any && options_.sky.value_or(scheduler);
  world.view<weather::WeatherZone>().each([&](ecs::Entity e, weather::WeatherZone& z) {
    if (const auto* n = world.try_get<ecs::Name>(e); z.name.empty() && n) z.name = n->value;
    for (const weather::ScheduleEntry& s : z.states) library().require(s.state, where(e, "WeatherZone"));
  });
  world.view<gameplay::Trigger>().each([&](ecs::Entity e, gameplay::Trigger& t) {
    for (const std::string& state : gameplay::trigger_weather_states(t))
      library().require(state, where(e, "Trigger set_weather"));
  });
}

void CloudFeature::extract(const ecs::World& world, cumulo::render::FrameSnapshot& snapshot) const {
  CloudFrame frame;
  world.view<const Cloudscape>().each([&](ecs::Entity e, const Cloudscape& c) {
    if (c.resolved.empty()) return;  // added after the level loaded: not resolved (the editor will)
    CloudInstanceFrame i;
    i.folder = c.resolved;
    if (const auto* t = world.try_get<scene::Transform>(e)) {
      i.position = t->position;
      i.rotation = t->rotation;
      i.scale = t->scale.x;
    }
    i.density = c.density;
    i.wind_direction = c.wind_direction;
    i.wind_speed = c.wind_speed;
    i.dissipation = c.dissipation;
    i.rain = c.rain;
    frame.instances.push_back(std::move(i));
  });
  // Live lightning flashes, brightest first: the renderer's point lights (a bluish white); a ground
  // discharge also shows its channel (a bolt down to sea level, hidden by the terrain where it stands
  // higher) and lights the terrain from the channel's foot, an internal flash the ground faintly.
  const glm::vec3 kLightningColor(0.75f, 0.8f, 1.0f);
  for (const gameplay::LightningLight& l : gameplay::lightning_lights(world, kMaxPointLights)) {
    frame.lights.push_back({l.position, l.radius, kLightningColor * l.intensity});
    if (l.kind == gameplay::LightningKind::Ground) {
      BoltFrame bolt;
      bolt.intensity = l.intensity;
      for (const gameplay::BoltSegment& g : gameplay::lightning_bolt(l.position, 0.0f, l.seed))
        bolt.segments.push_back({g.a, g.b, g.brightness});
      if (!bolt.segments.empty()) {
        const glm::vec3 foot = bolt.segments[gameplay::kBoltMainSegments - 1].b;
        snapshot.lighting.point_lights.push_back({foot + glm::vec3(0, 60, 0), 3000.0f, kLightningColor * (0.01f * l.intensity)});
      }
      frame.bolts.push_back(std::move(bolt));
    } else {
      snapshot.lighting.point_lights.push_back({l.position, 2000.0f, kLightningColor * (0.0015f * l.intensity)});
    }
  }
  if (weather_preview_) frame.weather = *weather_preview_;
  if (weather_lib_)
    world.view<const weather::WeatherScheduler>().each([&](const weather::WeatherScheduler& w) {
      if (!frame.weather) frame.weather = weather::weather_now(w, *weather_lib_).state;  // the first one counts
    });
  frame.sky.enabled = sky_enabled_;
  const weather::WeatherState* state = frame.weather ? &*frame.weather : options_.weather ? &*options_.weather : nullptr;
  if (state) {
    apply_weather(*state, frame.sky);
    // The weather's haze thickens the air's aerosols: the atmosphere's Mie density and the height fog.
    const float mie = haze_mie_scale(state->haze);
    snapshot.lighting.mie_scale = mie;
    snapshot.lighting.fog_density *= mie;
  }
  snapshot.extensions.set(std::move(frame));
}

void CloudFeature::create_gpu(cumulo::render::GpuServices& g) {
  ctx_ = &g.ctx;
  library_ = &g.library;
  cache_ = std::make_unique<CloudAssetCache>(g.ctx);
  if (noise_file_.empty()) return;  // the level has no cloudscape
  // The talk's 256x256x32 grid, or on CPU devices a smaller one (its eighth per frame would cost about
  // as much as the whole march there) unless --cloud-light-grid talk asks for the talk's.
  CloudResourcesDesc desc = options_.talk_light_grid ? CloudResourcesDesc{} : CloudResourcesDesc::for_device(g.ctx.info());
  resources_ = create_cloud_resources(g.ctx, g.library, cache_->noise(noise_file_), desc);
  effects_ = std::make_unique<CloudEffects>(g.ctx, g.library);
  if (sky_enabled_) sky_ = std::make_unique<SkyLayer>(g.ctx, g.library, prepare_sky_noise());
  if (options_.light_shafts) shafts_ = std::make_unique<LightShafts>(g.ctx, g.library);
}

void CloudFeature::destroy_gpu() {
  steps_buffer_.reset();
  steps_pixels_ = 0;
  sky_.reset();
  shafts_.reset();
  resources_.reset();
  effects_.reset();
  cache_.reset();
  ctx_ = nullptr;
  library_ = nullptr;
}

gpu::PipelineLibrary& CloudFeature::pipeline_library() {
  if (!library_) fail("clouds: the feature's GPU objects are not created yet");
  return *library_;
}

uint64_t CloudFeature::asset_gpu_bytes() const { return cache_ ? cache_->gpu_bytes() : 0; }

CloudFrameInputs CloudFeature::frame_inputs(const cumulo::render::StageContext& f, const CloudFrame& frame) {
  const cumulo::render::FrameSnapshot& s = f.snapshot;
  const CloudFormats formats = CloudFormats::from_set(options_.formats.value_or(default_format_set(ctx_->info())));
  CloudSettings settings;
  settings.ablation = options_.ablation;
  settings.debug = options_.debug;
  settings.temporal = options_.temporal;
  settings.light_grid_method = options_.light_grid_method;
  settings.light_sample_noise_mean = options_.light_sample_noise_mean;
  settings.light_grid_always_update = options_.light_grid_always_update;
  settings.reprojection_block = options_.reprojection_block;
  settings.shadows = options_.shadows;
  settings.terrain_shadow = options_.terrain_shadow;
  settings.effects = options_.effects;
  apply_lighting_preset(settings, options_.lighting);
  if (options_.ms_strength >= 0.0f) settings.ms_strength = options_.ms_strength;
  if (options_.ambient_occlusion >= 0.0f) settings.ambient_occlusion_scale = options_.ambient_occlusion;
  if (options_.ms_attenuation_inside >= 0.0f) settings.ms_attenuation_inside = options_.ms_attenuation_inside;
  if (options_.ms_other_clouds >= 0.0f) settings.ms_other_cloud_attenuation = options_.ms_other_clouds;
  if (options_.ms_enclosed >= 0.0f) settings.ms_enclosed_sky_depth = options_.ms_enclosed;
  if (options_.ground_albedo >= 0.0f) settings.ground_albedo = options_.ground_albedo;
  if (options_.ms_anisotropy >= 0.0f) settings.ms_anisotropy = options_.ms_anisotropy;
  if (options_.light_sample_m > 0.0f) settings.light_sample_m = options_.light_sample_m;
  if (options_.edge_depth >= 0.0f) settings.edge_depth_scale = options_.edge_depth;
  if (options_.ms_lateral >= 0.0f) settings.ms_lateral = options_.ms_lateral;
  if (options_.sky_mean >= 0) settings.sky_mean_ambient = options_.sky_mean == 1;
  if (options_.instance_shadows >= 0) settings.instance_shadows = options_.instance_shadows == 1;
  // Camera, time, budget mode, the sun (pi x the engine's Lambertian radiance) and the sky's ambient.
  CloudFrameInputs in = cloud_inputs_from_snapshot(s, f.slot, settings);
  for (const CloudInstanceFrame& i : frame.instances) {
    CloudInstance ci;
    static_cast<CloudPlacement&>(ci) = i;
    ci.asset = cache_->cloudscape(i.folder, formats);
    in.instances.push_back(std::move(ci));
  }
  in.lights = frame.lights;
  in.terrain_depth = f.light_depth.texture;
  in.terrain_depth_matrix = f.light_depth.world_to_light;
  in.terrain_depth_range_m = f.light_depth.depth_range_m;
  // The scheduler's weather of this frame, else the state --weather names.
  if (frame.weather) apply_weather(*frame.weather, in);
  else if (options_.weather) apply_weather(*options_.weather, in);
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
  if (!frame || frame->instances.empty()) return;
  // Before the scene: the light grid and the shadow map (the geometry reads it); after it, the rest.
  if (stage == Stage::BeforeScene) {
    inputs_ = frame_inputs(f, *frame);
    light_ = add_cloud_light_passes(*resources_, f.graph, *inputs_);
    if (light_.shadow.texture.valid()) f.light_shadow = light_.shadow;
    return;
  }
  if (!inputs_) return;  // (a renderer always runs BeforeScene first)
  CloudFrameInputs in = std::move(*inputs_);
  inputs_.reset();
  in.aerial = f.aerial_perspective;
  if (reference_) {
    // The path tracer draws the whole picture (clouds, terrain, sky) in place of the real-time passes.
    f.hdr = reference_->add_passes(f.graph, f.snapshot, in, light_, f.hdr, f.depth);
    light_ = {};
    if (hdr_capture_) hdr_capture_->add_pass(f.graph, f.hdr);
    return;
  }
  if (sky_ && !options_.reference_comparable) {
    const SkyLayer::Outputs o = sky_->add_passes(f.graph, frame->sky, in, f.depth);
    in.sky_color = o.color;
    in.sky_depth = o.depth;
  }
  const cumulo::render::FrameSnapshot& s = f.snapshot;
  // Rain columns under precipitating clouds: below the centre of the box, 0.3 of its smaller side wide,
  // from the cloud base to sea level (the scene depth stops them at the terrain), fading with dissipation.
  CloudEffectsInputs fx;
  fx.camera = s.camera;
  fx.time = s.sim_time;
  fx.slot = f.slot;
  fx.bolts = frame->bolts;
  fx.rain_light = in.ambient_color * 0.3f + in.sun_color * 0.01f;  // under the cloud: mostly shadowed
  for (size_t k = 0; k < frame->instances.size(); ++k) {
    const CloudInstanceFrame& i = frame->instances[k];
    const float intensity = i.rain * (1.0f - std::clamp(i.dissipation, 0.0f, 1.0f));
    if (!(intensity > 0.0f) || !options_.rain) continue;
    const CloudAsset& a = *in.instances[k].asset;
    const glm::vec3 base(0.5f * (a.bounds_min.x + a.bounds_max.x), a.bounds_min.y, 0.5f * (a.bounds_min.z + a.bounds_max.z));
    const glm::vec3 extent = a.bounds_max - a.bounds_min;
    fx.rain.push_back({i.position + glm::normalize(i.rotation) * (i.scale * base),
                       0.3f * i.scale * std::min(extent.x, extent.z), 0.0f, intensity});
  }
  const bool effects = (!fx.bolts.empty() || !fx.rain.empty()) && !options_.reference_comparable;
  CloudPassOutputs outputs;
  f.hdr = add_cloud_passes(*resources_, f.graph, in, f.hdr, f.depth, &outputs, &light_);
  light_ = {};
  if (measure_steps_ && outputs.depth.valid()) add_steps_readback(f, outputs.depth);
  if (effects) f.hdr = effects_->add_passes(f.graph, fx, f.hdr, f.depth, outputs);
  if (shafts_ && !options_.reference_comparable) {
    LightShaftInputs li;
    li.camera = s.camera;
    li.slot = f.slot;
    li.sun_direction = in.sun_direction;
    li.sun_color = in.sun_color;
    li.haze_density = in.haze_density;
    li.haze_falloff = in.haze_falloff;
    f.hdr = shafts_->add_passes(f.graph, li, f.hdr, f.depth, outputs, in.sky_color);
  }
  if (hdr_capture_) hdr_capture_->add_pass(f.graph, f.hdr);
}

void CloudFeature::add_steps_readback(cumulo::render::StageContext& f, cumulo::render::TextureHandle depth) {
  using namespace cumulo::render;
  const VkExtent2D size = f.graph.output_size();
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
