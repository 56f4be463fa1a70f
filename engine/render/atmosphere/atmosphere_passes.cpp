#include "engine/render/atmosphere/atmosphere_passes.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"

namespace cumulo::render {
namespace {

constexpr VkFormat kLutFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

gpu::Image lut_image(gpu::Context& ctx, uint32_t w, uint32_t h, const char* name) {
  return gpu::Image(ctx, gpu::ImageDesc::tex2d(w, h, kLutFormat, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1, name));
}
PersistentTexture persistent(const gpu::Image& img, const char* name) {
  return {name, TextureDesc::absolute(kLutFormat, img.extent().width, img.extent().height), img.handle(), img.view(),
          ResourceState::undefined()};
}

}  // namespace

AtmospherePasses::AtmospherePasses(gpu::Context& ctx, gpu::PipelineLibrary& library, const Atmosphere& atmosphere)
    : ctx_(ctx), atmosphere_(atmosphere) {
  transmittance_pipe_ = &library.compute({.shader = "engine/atmosphere_transmittance.comp", .name = "atmosphere.transmittance"});
  ms_pipe_ = &library.compute({.shader = "engine/atmosphere_multiscatter.comp", .name = "atmosphere.multiscatter"});
  sky_view_pipe_ = &library.compute({.shader = "engine/atmosphere_sky_view.comp", .name = "atmosphere.sky_view"});
  aerial_pipe_ = &library.compute({.shader = "engine/atmosphere_aerial.comp", .name = "atmosphere.aerial_perspective"});
  transmittance_ = lut_image(ctx, ATMOSPHERE_TRANSMITTANCE_W, ATMOSPHERE_TRANSMITTANCE_H, "atmosphere.transmittance");
  ms_ = lut_image(ctx, ATMOSPHERE_MS_SIZE, ATMOSPHERE_MS_SIZE, "atmosphere.multiscatter");
  sky_view_ = lut_image(ctx, ATMOSPHERE_SKY_VIEW_W, ATMOSPHERE_SKY_VIEW_H, "atmosphere.sky_view");
  transmittance_tex_ = persistent(transmittance_, "atmosphere.transmittance");
  ms_tex_ = persistent(ms_, "atmosphere.multiscatter");
  sky_view_tex_ = persistent(sky_view_, "atmosphere.sky_view");
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    ubo_[i] = gpu::Buffer(ctx, {sizeof(shared::AtmosphereGpuParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                gpu::MemoryUsage::Dynamic, i ? "atmosphere.params.1" : "atmosphere.params.0"});
  linear_ = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
}

float AtmospherePasses::mie_scale_key(const FrameSnapshot& s) {
  const float m = std::clamp(s.lighting.mie_scale, 0.05f, 20.0f);
  return std::round(m * 20.0f) / 20.0f;
}

shared::AtmosphereGpuParams AtmospherePasses::gpu_params(const FrameSnapshot& s) const {
  const AtmosphereParams& p = atmosphere_.params();
  shared::AtmosphereGpuParams g{};
  g.radii = glm::vec4(p.bottom_radius_km, p.top_radius_km, p.rayleigh_scale_height_km, p.mie_scale_height_km);
  g.rayleigh = glm::vec4(p.rayleigh_scattering, p.mie_g);
  const float haze = mie_scale_key(s);
  g.mie = glm::vec4(p.mie_scattering * haze, p.mie_extinction * haze, p.ozone_center_km, p.ozone_width_km);
  g.ozone = glm::vec4(p.ozone_absorption, Atmosphere::kAirglow);
  g.albedo = glm::vec4(p.ground_albedo, p.solar_irradiance);
  const glm::vec3 sun = glm::normalize(s.sun.direction);
  g.sun = glm::vec4(sun, 1.0f);
  g.moon = glm::vec4(-sun, atmosphere_.moon_weight(s.sun.elevation_deg));
  g.view = glm::vec4(std::max(s.camera.position.y, 0.0f) * 0.001f, glm::radians(p.sun_angular_radius_deg), 0.0f, 0.0f);
  return g;
}

AtmosphereLuts AtmospherePasses::add_passes(RenderGraph& graph, const FrameSnapshot& s, uint32_t slot) {
  const gpu::Buffer& ubo = ubo_[slot % gpu::kFramesInFlight];
  const shared::AtmosphereGpuParams params = gpu_params(s);
  std::memcpy(ubo.mapped(), &params, sizeof params);
  const VkBuffer ubo_handle = ubo.handle();
  TextureHandle trans = graph.import_persistent(transmittance_tex_);
  TextureHandle ms = graph.import_persistent(ms_tex_);
  TextureHandle view = graph.import_persistent(sky_view_tex_);
  gpu::Context* ctx = &ctx_;
  const VkSampler linear = linear_;
  auto dispatch = [ctx, ubo_handle](gpu::Pipeline* pipe, VkCommandBuffer cmd, gpu::DescriptorWriter& w, uint32_t wd, uint32_t ht) {
    w.uniform_buffer(ATMOSPHERE_PARAMS_BINDING, ubo_handle, 0, sizeof(shared::AtmosphereGpuParams));
    pipe->bind(cmd);
    w.push(*ctx, cmd, *pipe);
    pipe->dispatch_threads(cmd, wd, ht);
  };
  if (!luts_built_ || params.mie.x != built_mie_) {
    // The preset's LUTs: once, and again when the weather's haze changes the Mie density (in steps of
    // 5 %: mie_scale_key). A preset change builds a new AtmospherePasses.
    gpu::Pipeline* tp = transmittance_pipe_;
    graph.add_pass("atmosphere.transmittance", Queue::Compute,
        [&](PassBuilder& b) { trans = b.write(trans, Usage::StorageWrite); },
        [tp, trans, dispatch](PassContext& c) {
          gpu::DescriptorWriter w;
          w.storage_image(ATMOSPHERE_OUT_BINDING, c.view(trans));
          dispatch(tp, c.cmd(), w, ATMOSPHERE_TRANSMITTANCE_W, ATMOSPHERE_TRANSMITTANCE_H);
        });
    gpu::Pipeline* mp = ms_pipe_;
    graph.add_pass("atmosphere.multiscatter", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(trans, Usage::Sampled);
          ms = b.write(ms, Usage::StorageWrite);
        },
        [mp, trans, ms, linear, dispatch](PassContext& c) {
          gpu::DescriptorWriter w;
          w.sampled_image(ATMOSPHERE_TRANSMITTANCE_BINDING, c.view(trans), linear, c.layout(trans))
              .storage_image(ATMOSPHERE_OUT_BINDING, c.view(ms));
          dispatch(mp, c.cmd(), w, ATMOSPHERE_MS_SIZE, ATMOSPHERE_MS_SIZE);
        });
    luts_built_ = true;
    built_mie_ = params.mie.x;
    ++lut_builds_;
    have_key_ = false;
  }
  // The sky view follows the sun (a tenth of a degree), the moon's weight and the camera's altitude (10 m).
  const glm::vec4 key(params.sun.x, params.sun.y, params.sun.z, std::round(params.view.x * 100.0f));
  const bool stale = !have_key_ || glm::dot(glm::vec3(key), glm::vec3(sky_key_)) < std::cos(glm::radians(0.1f)) ||
                     key.w != sky_key_.w || params.moon.w != moon_key_;
  if (stale) {
    gpu::Pipeline* vp = sky_view_pipe_;
    graph.add_pass("atmosphere.sky_view", Queue::Compute,
        [&](PassBuilder& b) {
          b.read(trans, Usage::Sampled);
          b.read(ms, Usage::Sampled);
          view = b.write(view, Usage::StorageWrite);
        },
        [vp, trans, ms, view, linear, dispatch](PassContext& c) {
          gpu::DescriptorWriter w;
          w.sampled_image(ATMOSPHERE_TRANSMITTANCE_BINDING, c.view(trans), linear, c.layout(trans))
              .sampled_image(ATMOSPHERE_MS_BINDING, c.view(ms), linear, c.layout(ms))
              .storage_image(ATMOSPHERE_OUT_BINDING, c.view(view));
          dispatch(vp, c.cmd(), w, ATMOSPHERE_SKY_VIEW_W, ATMOSPHERE_SKY_VIEW_H);
        });
    sky_key_ = key;
    moon_key_ = params.moon.w;
    have_key_ = true;
    ++sky_view_updates_;
  }
  // The aerial-perspective froxels follow the camera: every frame.
  TextureDesc ad = TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, ATMOSPHERE_AERIAL_SIZE, ATMOSPHERE_AERIAL_SIZE,
                                         ATMOSPHERE_AERIAL_SIZE);
  ad.type = ImageType::Image3D;
  TextureHandle aerial = graph.create_texture("atmosphere.aerial_perspective", ad);
  gpu::Pipeline* ap = aerial_pipe_;
  shared::AtmosphereAerialPush push{};
  push.inv_view_proj = s.camera.inv_view_proj;
  push.camera = glm::vec4(s.camera.position, 0.0f);
  graph.add_pass("atmosphere.aerial_perspective", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(trans, Usage::Sampled);
        b.read(ms, Usage::Sampled);
        aerial = b.write(aerial, Usage::StorageWrite);
      },
      [ap, trans, ms, aerial, linear, ctx, ubo_handle, push](PassContext& c) {
        gpu::DescriptorWriter w;
        w.uniform_buffer(ATMOSPHERE_PARAMS_BINDING, ubo_handle, 0, sizeof(shared::AtmosphereGpuParams))
            .sampled_image(ATMOSPHERE_TRANSMITTANCE_BINDING, c.view(trans), linear, c.layout(trans))
            .sampled_image(ATMOSPHERE_MS_BINDING, c.view(ms), linear, c.layout(ms))
            .storage_image(ATMOSPHERE_OUT_BINDING, c.view(aerial));
        ap->bind(c.cmd());
        w.push(*ctx, c.cmd(), *ap);
        ap->push_constants(c.cmd(), push);
        ap->dispatch_threads(c.cmd(), ATMOSPHERE_AERIAL_SIZE, ATMOSPHERE_AERIAL_SIZE);
      });
  return {trans, view, ubo_handle, aerial};
}

}  // namespace cumulo::render
