#include "modules/clouds/reference/reference_tracer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "engine/render/pass_helpers.h"
#include "engine/render/sky_model.h"
#include "modules/clouds/render/pass_bindings.h"
#include "shaders/shared/envelope_params.h"
#include "shaders/shared/reference_params.h"

namespace cumulo::clouds::render {

using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::ResourceState;
using cumulo::render::TextureDesc;
using cumulo::render::Usage;

namespace {
constexpr VkFormat kAccumFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr uint32_t kMajorantBinding[kMaxAssets] = {REF_BINDING_MAJORANT, REF_BINDING_MAJORANT_1, REF_BINDING_MAJORANT_2};
}


MiePhase MiePhase::for_droplet(float d) {
  d = std::clamp(d, 5.0f, 50.0f);  // the fit's range
  MiePhase m;
  m.g_hg = std::exp(-0.0990567f / (d - 1.67154f));
  m.g_draine = std::exp(-2.20679f / (d + 3.91029f) - 0.428934f);
  m.alpha = std::exp(3.62489f - 8.29288f / (d + 5.52825f));
  m.w_draine = std::exp(-0.599085f / (d - 0.641583f) - 0.665888f);
  return m;
}

ReferenceTracer::ReferenceTracer(gpu::Context& ctx, gpu::PipelineLibrary& library) : ctx_(ctx), library_(library) {
  if (!ctx.info().push_descriptors)
    fail("%s: the path-traced reference needs VK_KHR_push_descriptor, which this device lacks", ctx.info().name.c_str());
  majorant_pipe_ = &library.compute({.shader = "clouds/reference_majorant.comp", .name = "clouds.reference_majorant"});
  resolve_pipe_ = &library.compute({.shader = "clouds/reference_resolve.comp", .name = "clouds.reference_resolve"});
  trace_pipeline(false, 1);
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i) {
    cloud_ubo_[i] = gpu::Buffer(ctx, {sizeof(shared::CloudParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                                      "clouds.reference.cloud_params"});
    ref_ubo_[i] = gpu::Buffer(ctx, {sizeof(shared::ReferenceParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                    gpu::MemoryUsage::Dynamic, "clouds.reference.params"});
  }
  linear_clamp_ = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  linear_repeat_ = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
  nearest_clamp_ = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
  // Stand-ins for what a frame may lack (no terrain, no sky table, no aerial froxels): every binding is bound.
  const glm::vec4 zero(0.0f);
  no_terrain_ = gpu::Image(ctx, gpu::ImageDesc::tex2d(1, 1, kAccumFormat, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "clouds.reference.no_terrain"));
  no_terrain_.upload({{&zero, sizeof zero}});
  no_sky_ = gpu::Image(ctx, gpu::ImageDesc::tex2d(1, 1, kAccumFormat, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "clouds.reference.no_sky"));
  no_sky_.upload({{&zero, sizeof zero}});
  const uint16_t ap[4] = {0, 0, 0, 0x3c00};  // (0, 0, 0, 1) in half floats: no haze
  no_aerial_ = gpu::Image(ctx, gpu::ImageDesc::tex3d(1, 1, 1, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                    "clouds.reference.no_aerial"));
  no_aerial_.upload({{ap, sizeof ap}});
  const uint16_t none[4] = {0, 0, 0, 0};
  no_volume_ = gpu::Image(ctx, gpu::ImageDesc::tex3d(1, 1, 1, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                    "clouds.reference.no_volume"));
  no_volume_.upload({{none, sizeof none}});
}

ReferenceTracer::~ReferenceTracer() { ctx_.wait_idle(); }

gpu::Pipeline& ReferenceTracer::trace_pipeline(bool analytic, int asset_slots, bool coverage_texture, bool envelope) {
  const auto key = std::make_tuple(analytic, analytic ? 1 : asset_slots, coverage_texture && !analytic, envelope && !analytic);
  auto it = trace_pipes_.find(key);
  if (it != trace_pipes_.end()) return *it->second;
  const int slots = std::get<1>(key);
  const bool coverage = std::get<2>(key);
  const bool env = std::get<3>(key);
  gpu::Pipeline& p = library_.compute(
      {.shader = "clouds/reference_trace.comp",
       .defines = {{"MEDIUM", analytic ? "1" : "0"},
                   {"CLOUD_ASSET_SLOTS", std::to_string(slots)},
                   {"COVERAGE_TEXTURE", coverage ? "1" : "0"},
                   {"ENVELOPE", env ? "1" : "0"}},
       .name = std::string("clouds.reference_trace") +
               (analytic ? " (analytic medium)" : slots > 1 ? " (" + std::to_string(slots) + " assets)" : "") + (coverage ? " (coverage texture)" : "") +
               (env ? " (envelope)" : "")});
  trace_pipes_[key] = &p;
  return p;
}

void ReferenceTracer::set_terrain(const TerrainHeightfield& t) {
  ctx_.wait_idle();  // a frame in flight may read the old one
  terrain_cpu_ = t;
  terrain_ = {};
  if (t.empty()) return;
  terrain_ = gpu::Image(ctx_, gpu::ImageDesc::tex2d(t.resolution, t.resolution, kAccumFormat, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                    "clouds.reference.terrain"));
  terrain_.upload({{t.texels.data(), t.texels.size() * sizeof(glm::vec4)}});
}

void ReferenceTracer::set_sky(const SkyEnvironment& s) {
  ctx_.wait_idle();
  sky_ = {};
  if (s.texels.empty()) return;
  sky_ = gpu::Image(ctx_, gpu::ImageDesc::tex2d(s.width, s.height, kAccumFormat, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                "clouds.reference.sky"));
  sky_.upload({{s.texels.data(), s.texels.size() * sizeof(glm::vec4)}});
}

void ReferenceTracer::prepare_scene(const cumulo::render::FrameSnapshot& s) {
  const void* models = s.models.empty() ? nullptr : s.models.front().model.get();
  if (models != scene_models_ || s.models.size() != scene_model_count_) {
    set_terrain(rasterize_heightfield(s.models));
    scene_models_ = models;
    scene_model_count_ = s.models.size();
  }
  if (s.ocean) set_ocean(glm::vec4(s.ocean->color, s.ocean->sea_level));
  else set_ocean(std::nullopt);
  // The sky table depends on the sun, the camera's altitude (to 10 m) and the haze.
  const glm::vec3 sun = glm::normalize(s.sun.direction);
  const glm::vec4 key(sun.x + 10.0f * std::round(s.camera.position.y / 10.0f), sun.y, sun.z, s.lighting.mie_scale);
  if (!sky_ || key != sky_key_) {
    set_sky(sky_environment(s));
    sky_key_ = key;
  }
}

cumulo::render::TextureHandle ReferenceTracer::add_passes(cumulo::render::RenderGraph& graph,
                                                          const cumulo::render::FrameSnapshot& snapshot,
                                                          const CloudFrameInputs& in, const CloudLightOutputs& light,
                                                          cumulo::render::TextureHandle hdr,
                                                          cumulo::render::TextureHandle depth) {
  prepare_scene(snapshot);
  return add_passes(graph, in, light, hdr, depth);
}

cumulo::render::TextureHandle ReferenceTracer::add_passes(cumulo::render::RenderGraph& graph, const CloudFrameInputs& in,
                                                          const CloudLightOutputs& light,
                                                          cumulo::render::TextureHandle hdr,
                                                          cumulo::render::TextureHandle depth) {
  const ReferenceSettings& rs = settings_;
  const bool analytic = rs.analytic.has_value();
  if (!analytic && !in.instances.empty() && light.modelings.empty())
    fail("clouds: the reference needs the frame's cloud light passes (add_cloud_light_passes) for its asset imports");
  const VkExtent2D size = graph.output_size();
  const uint32_t slot = in.slot % gpu::kFramesInFlight;

  // ---- Accumulation images (persistent; a new size restarts the accumulation) ----
  if (!accum_image_ || accum_image_.extent().width != size.width || accum_image_.extent().height != size.height) {
    ctx_.wait_idle();
    const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    accum_image_ = gpu::Image(ctx_, gpu::ImageDesc::tex2d(size.width, size.height, kAccumFormat, usage, 1, "clouds.reference.accum"));
    aux_image_ = gpu::Image(ctx_, gpu::ImageDesc::tex2d(size.width, size.height, kAccumFormat, usage, 1, "clouds.reference.aux"));
    accum_ = {"clouds.reference.accum", TextureDesc::absolute(kAccumFormat, size.width, size.height), accum_image_.handle(),
              accum_image_.view(), ResourceState::undefined()};
    aux_ = {"clouds.reference.aux", TextureDesc::absolute(kAccumFormat, size.width, size.height), aux_image_.handle(),
            aux_image_.view(), ResourceState::undefined()};
    const VkDeviceSize bytes = VkDeviceSize(size.width) * size.height * sizeof(glm::vec4);
    accum_readback_ = gpu::Buffer(ctx_, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "clouds.reference.accum readback"});
    aux_readback_ = gpu::Buffer(ctx_, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, gpu::MemoryUsage::Readback, "clouds.reference.aux readback"});
    samples_ = 0;
  }

  // ---- Parameters ----
  shared::CloudParams cp = cloud_params(in, size, light.slots);
  std::memcpy(cloud_ubo_[slot].mapped(), &cp, sizeof cp);
  shared::ReferenceParams rp{};
  const uint32_t count = std::max(1u, rs.samples_per_frame);
  rp.settings = glm::vec4(float(std::max(1u, rs.max_bounces)), float(int(rs.phase)), float(samples_), float(count));
  const bool terrain = rs.terrain && !terrain_cpu_.empty() && terrain_;
  const bool aerial = rs.aerial && in.aerial.valid();
  uint32_t flags = REF_FLAG_SCENE_DEPTH;
  if (rs.sun) flags |= REF_FLAG_SUN;
  if (rs.sky) flags |= REF_FLAG_SKY;
  if (terrain) flags |= REF_FLAG_TERRAIN;
  if (aerial) flags |= REF_FLAG_AERIAL;
  if (analytic) flags |= REF_FLAG_ANALYTIC;
  if (ocean_ && rs.terrain) flags |= REF_FLAG_OCEAN;
  rp.flags = glm::uvec4(flags, rs.seed, rs.lights ? uint32_t(std::min<size_t>(in.lights.size(), kMaxPointLights)) : 0u, 0u);
  if (terrain) {
    rp.terrain = glm::vec4(terrain_cpu_.origin, terrain_cpu_.size);
    rp.terrain_range = glm::vec4(terrain_cpu_.min_height, terrain_cpu_.max_height, 0.0f, ocean_ ? ocean_->w : -1e9f);
  } else {
    rp.terrain = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
    rp.terrain_range = glm::vec4(0.0f, 0.0f, 0.0f, ocean_ ? ocean_->w : -1e9f);
  }
  if (ocean_) rp.ocean_albedo = glm::vec4(glm::vec3(*ocean_), 0.0f);
  rp.env = glm::vec4(sky_ ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f);
  const MiePhase mie = MiePhase::for_droplet(rs.droplet_um);
  rp.mie = glm::vec4(mie.g_hg, mie.g_draine, mie.alpha, mie.w_draine);
  rp.medium = glm::vec4(0.0f, rs.uniform_sky, rs.uniform_sky_upper_only ? 1.0f : 0.0f, 0.0f);
  if (analytic) {
    const AnalyticMedium& m = *rs.analytic;
    rp.medium_min = glm::vec4(m.min, m.extinction);
    rp.medium_max = glm::vec4(m.max, m.albedo);
    rp.medium.x = std::max(m.majorant, m.extinction);
  }
  rp.light_scale = glm::vec4(rs.light_scale, 0.0f, 0.0f, 0.0f);
  std::memcpy(ref_ubo_[slot].mapped(), &rp, sizeof rp);
  const VkBuffer cloud_ubo = cloud_ubo_[slot].handle(), ref_ubo = ref_ubo_[slot].handle();

  // ---- Imports ----
  auto import_2d = [&](const std::string& name, const gpu::Image& img) {
    const VkExtent3D e = img.extent();
    return graph.import_texture(name, TextureDesc::absolute(img.format(), e.width, e.height), img.handle(), img.view(),
                                ResourceState::shader_read_only());
  };
  auto import_3d = [&](const std::string& name, const gpu::Image& img) {
    const VkExtent3D e = img.extent();
    TextureDesc d = TextureDesc::absolute(img.format(), e.width, e.height, e.depth);
    d.type = cumulo::render::ImageType::Image3D;
    return graph.import_texture(name, d, img.handle(), img.view(), ResourceState::shader_read_only());
  };
  const cumulo::render::TextureHandle terrain_tex = import_2d("clouds.reference.terrain", terrain ? terrain_ : no_terrain_);
  const cumulo::render::TextureHandle sky_tex = import_2d("clouds.reference.sky", sky_ ? sky_ : no_sky_);
  const cumulo::render::TextureHandle aerial_tex = aerial ? in.aerial : import_3d("clouds.reference.no_aerial", no_aerial_);
  // Without voxel instances (the envelope clouds alone) the instances' loops never run, but their bindings are bound.
  const bool no_instances = !analytic && light.modelings.empty();

  // Majorant grids, one per asset slot (built once per asset, again when a growing cloud's images change).
  std::vector<cumulo::render::TextureHandle> majorants;
  if (!analytic) {
    std::vector<const CloudAsset*> slot_assets(light.modelings.size(), nullptr);
    for (size_t i = 0; i < in.instances.size() && i < light.slots.size(); ++i) slot_assets[light.slots[i]] = in.instances[i].asset.get();
    for (size_t a = 0; a < slot_assets.size(); ++a) {
      Majorant& m = majorants_[slot_assets[a]];
      if (!m.image) {
        const VkExtent3D e = slot_assets[a]->modeling_image().extent();
        const glm::uvec3 cells((e.width + REF_MAJORANT_CELL - 1) / REF_MAJORANT_CELL, (e.height + REF_MAJORANT_CELL - 1) / REF_MAJORANT_CELL,
                               (e.depth + REF_MAJORANT_CELL - 1) / REF_MAJORANT_CELL);
        m.image = gpu::Image(ctx_, gpu::ImageDesc::tex3d(cells.x, cells.y, cells.z, VK_FORMAT_R32_SFLOAT,
                                                         VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1,
                                                         "clouds.reference.majorant"));
        TextureDesc d = TextureDesc::absolute(VK_FORMAT_R32_SFLOAT, cells.x, cells.y, cells.z);
        d.type = cumulo::render::ImageType::Image3D;
        m.texture = {"clouds.reference.majorant" + (a ? "." + std::to_string(a) : std::string()), d, m.image.handle(), m.image.view(),
                     ResourceState::undefined()};
      }
      cumulo::render::TextureHandle h = graph.import_persistent(m.texture);
      if (m.revision != slot_assets[a]->revision) {
        const cumulo::render::TextureHandle modeling = light.modelings[a];
        gpu::Pipeline* pipe = majorant_pipe_;
        graph.add_pass(a ? "clouds.reference_majorant." + std::to_string(a) : std::string("clouds.reference_majorant"), Queue::Compute,
            [&](PassBuilder& b) {
              b.read(modeling, Usage::Sampled);
              h = b.write(h, Usage::StorageWrite);
              b.side_effect();
            },
            [this, pipe, modeling, h](PassContext& c) {
              PassBindings(*pipe)
                  .sampled(REF_BINDING_MODELING_IN, c.view(modeling), nearest_clamp_, c.layout(modeling))
                  .storage(REF_BINDING_MAJORANT_OUT, c.view(h))
                  .push(ctx_, c.cmd());
              const VkExtent3D e = c.extent(h);
              shared::ReferenceMajorantPush pc{};
              pc.cells = glm::ivec4(int(e.width), int(e.height), int(e.depth), 0);
              pipe->push_constants(c.cmd(), pc);
              pipe->dispatch_threads(c.cmd(), e.width, e.height, e.depth);
            });
        m.revision = slot_assets[a]->revision;
      }
      majorants.push_back(h);
    }
  }

  // ---- Trace ----
  const CloudFrameInputs::EnvelopeMedium envelope = analytic ? CloudFrameInputs::EnvelopeMedium{} : in.envelope_medium;
  const bool with_envelope = envelope.valid();
  gpu::Pipeline* trace =
      &trace_pipeline(analytic, int(std::max<size_t>(1, light.modelings.size())), light.coverage_texture, with_envelope);
  cumulo::render::TextureHandle accum = graph.import_persistent(accum_), aux = graph.import_persistent(aux_);
  std::vector<cumulo::render::TextureHandle> modelings = light.modelings;
  cumulo::render::TextureHandle noise = light.noise;
  if (no_instances) {
    const cumulo::render::TextureHandle none = import_3d("clouds.reference.no_volume", no_volume_);
    modelings = {none};
    noise = none;
    majorants = {none};
  }
  const std::vector<cumulo::render::TextureHandle> coverages = analytic ? std::vector<cumulo::render::TextureHandle>{} : light.coverages;
  graph.add_pass("clouds.reference_trace", Queue::Compute,
      [&](PassBuilder& b) {
        if (!analytic) {
          for (cumulo::render::TextureHandle m : modelings) b.read(m, Usage::Sampled);
          for (cumulo::render::TextureHandle m : coverages) b.read(m, Usage::Sampled);
          for (cumulo::render::TextureHandle m : majorants) b.read(m, Usage::Sampled);
          b.read(noise, Usage::Sampled);
        }
        if (with_envelope)
          for (cumulo::render::TextureHandle t : {envelope.shape, envelope.steps, envelope.aux, envelope.base_noise, envelope.detail_noise})
            b.read(t, Usage::Sampled);
        b.read(depth, Usage::Sampled);
        b.read(terrain_tex, Usage::Sampled);
        b.read(sky_tex, Usage::Sampled);
        b.read(aerial_tex, Usage::Sampled);
        accum = b.read_write(accum, Usage::StorageWrite);
        aux = b.read_write(aux, Usage::StorageWrite);
      },
      [this, trace, analytic, modelings, coverages, majorants, noise, depth, terrain_tex, sky_tex, aerial_tex, accum, aux, cloud_ubo,
       ref_ubo, envelope, with_envelope](PassContext& c) {
        PassBindings bind(*trace);
        bind.ubo(CLOUD_BINDING_PARAMS, cloud_ubo, sizeof(shared::CloudParams))
            .ubo(REF_BINDING_PARAMS, ref_ubo, sizeof(shared::ReferenceParams))
            .sampled(CLOUD_BINDING_SCENE_DEPTH, c.view(depth), nearest_clamp_, c.layout(depth))
            .sampled(REF_BINDING_TERRAIN, c.view(terrain_tex), linear_clamp_, c.layout(terrain_tex))
            .sampled(REF_BINDING_ENV, c.view(sky_tex), linear_clamp_, c.layout(sky_tex))
            .sampled(REF_BINDING_AERIAL, c.view(aerial_tex), linear_clamp_, c.layout(aerial_tex))
            .storage(REF_BINDING_ACCUM, c.view(accum))
            .storage(REF_BINDING_AUX, c.view(aux));
        if (!analytic) {
          bind.sampled(CLOUD_BINDING_MODELING, c.view(modelings[0]), linear_clamp_, c.layout(modelings[0]))
              .sampled(CLOUD_BINDING_NOISE, c.view(noise), linear_repeat_, c.layout(noise))
              .sampled(REF_BINDING_MAJORANT, c.view(majorants[0]), nearest_clamp_, c.layout(majorants[0]));
          for (size_t a = 1; a < modelings.size(); ++a)
            bind.sampled(kModelingBinding[a], c.view(modelings[a]), linear_clamp_, c.layout(modelings[a]))
                .sampled(kMajorantBinding[a], c.view(majorants[a]), nearest_clamp_, c.layout(majorants[a]));
          for (size_t a = 0; a < coverages.size(); ++a)
            bind.sampled(kCoverageBinding[a], c.view(coverages[a]), linear_clamp_, c.layout(coverages[a]));
        }
        if (with_envelope) {
          constexpr uint32_t o = ENV_BINDING_REFERENCE_OFFSET;
          bind.ubo(o + ENV_BINDING_PARAMS, envelope.params, sizeof(shared::EnvelopeParams))
              .sampled(o + ENV_BINDING_SHAPE, c.view(envelope.shape), linear_clamp_, c.layout(envelope.shape))
              .sampled(o + ENV_BINDING_STEPS, c.view(envelope.steps), nearest_clamp_, c.layout(envelope.steps))
              .sampled(o + ENV_BINDING_AUX, c.view(envelope.aux), linear_clamp_, c.layout(envelope.aux))
              .sampled(o + ENV_BINDING_BASE_NOISE, c.view(envelope.base_noise), linear_repeat_, c.layout(envelope.base_noise))
              .sampled(o + ENV_BINDING_DETAIL_NOISE, c.view(envelope.detail_noise), linear_repeat_,
                       c.layout(envelope.detail_noise));
        }
        bind.push(ctx_, c.cmd());
        const VkExtent3D e = c.extent(accum);
        trace->dispatch_threads(c.cmd(), e.width, e.height);
      });
  samples_ += count;

  // ---- Resolve into the scene colour ----
  gpu::Pipeline* resolve = resolve_pipe_;
  graph.add_pass("clouds.reference_resolve", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(accum, Usage::StorageRead);
        b.read(aux, Usage::StorageRead);
        hdr = b.write(hdr, Usage::StorageWrite);  // every pixel
      },
      [this, resolve, accum, aux, hdr](PassContext& c) {
        PassBindings(*resolve)
            .storage(REF_BINDING_ACCUM, c.view(accum))
            .storage(REF_BINDING_AUX, c.view(aux))
            .storage(REF_BINDING_HDR, c.view(hdr))
            .push(ctx_, c.cmd());
        const VkExtent3D e = c.extent(hdr);
        resolve->dispatch_threads(c.cmd(), e.width, e.height);
      });

  // ---- Readback (a copy per frame: the command reads the last one) ----
  cumulo::render::add_readback_pass(graph, "clouds.reference_readback",
                                    {{accum, accum_readback_.handle()}, {aux, aux_readback_.handle()}}, accum_readback_.size());
  return hdr;
}

ReferenceImage ReferenceTracer::read() const {
  ReferenceImage img;
  if (!accum_image_) return img;
  img.width = accum_image_.extent().width, img.height = accum_image_.extent().height;
  const size_t n = size_t(img.width) * img.height;
  std::vector<glm::vec4> accum(n), aux(n);
  accum_readback_.download(accum.data(), n * sizeof(glm::vec4));
  aux_readback_.download(aux.data(), n * sizeof(glm::vec4));
  img.radiance.resize(n);
  img.luminance_stderr.resize(n);
  img.samples = n ? uint32_t(aux[0].y) : 0;
  for (size_t i = 0; i < n; ++i) {
    const double s = std::max(1.0f, aux[i].y);
    const glm::vec3 mean = glm::vec3(accum[i]) / float(s);
    const double lum = 0.2126 * mean.r + 0.7152 * mean.g + 0.0722 * mean.b;
    const double var = s > 1 ? std::max(0.0, (accum[i].a / s - lum * lum) * s / (s - 1.0)) : 0.0;
    img.radiance[i] = glm::vec4(mean, 1.0f - aux[i].x / float(s));
    img.luminance_stderr[i] = float(std::sqrt(var / s));
    img.majorant_violations += aux[i].z;
  }
  return img;
}

}  // namespace cumulo::clouds::render
