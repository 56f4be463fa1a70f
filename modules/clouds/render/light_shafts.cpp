#include "modules/clouds/render/light_shafts.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::render {
using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::ResourceState;
using cumulo::render::TextureDesc;
using cumulo::render::TextureHandle;
using cumulo::render::Usage;

LightShafts::LightShafts(gpu::Context& ctx, gpu::PipelineLibrary& library) : ctx_(ctx) {
  shafts_ = &library.compute({.shader = "clouds/light_shafts.comp", .name = "clouds.light_shafts"});
  apply_ = &library.compute({.shader = "clouds/light_shafts_apply.comp", .name = "clouds.light_shafts_apply"});
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    ubo_[i] = gpu::Buffer(ctx, {sizeof(shared::CloudShaftParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                gpu::MemoryUsage::Dynamic, "clouds.light_shafts.params"});
  white_ = gpu::Image(ctx, gpu::ImageDesc::tex2d(1, 1, VK_FORMAT_R16G16B16A16_SFLOAT, VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                 "clouds.light_shafts.no_sky"));
  const uint16_t texel[4] = {0, 0, 0, 0x3C00};  // radiance 0, transmittance 1
  white_.upload({{texel, sizeof texel}});
  linear_ = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  nearest_ = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
}

bool LightShafts::active(const LightShaftInputs& in) {
  const glm::vec3 l = glm::normalize(in.sun_direction);
  if (!(l.y > -0.02f && in.haze_density > 0.0f && in.strength > 0.0f)) return false;
  // Only when the highlight around the sun reaches the view: the angle between the view's axis and the
  // sun within the half-diagonal of the view plus the highlight's radius (elsewhere the mask is 1).
  const float half_h = 0.5f * in.camera.fov_y, half_w = std::atan(std::tan(half_h) * in.camera.aspect);
  const float half_diag = std::atan(std::hypot(std::tan(half_h), std::tan(half_w)));
  const float angle = std::acos(std::clamp(glm::dot(l, glm::normalize(in.camera.forward)), -1.0f, 1.0f));
  return angle < half_diag + glm::radians(in.highlight_degrees);
}

TextureHandle LightShafts::add_passes(cumulo::render::RenderGraph& graph, const LightShaftInputs& in, TextureHandle hdr,
                                      TextureHandle depth, const CloudPassOutputs& clouds, TextureHandle sky_color) {
  if (!active(in) || !clouds.color.valid() || !clouds.depth.valid()) return hdr;
  const glm::vec3 l = glm::normalize(in.sun_direction);
  shared::CloudShaftParams p{};
  p.inv_view_proj = in.camera.inv_view_proj;
  p.view_proj = in.camera.view_proj;
  p.camera_pos = glm::vec4(in.camera.position, 0.0f);
  p.sun_dir = glm::vec4(l, std::cos(glm::radians(in.highlight_degrees)));
  // The sun's screen position: a point far along its direction, projected (Vulkan NDC, y down).
  const glm::vec4 c = in.camera.view_proj * glm::vec4(in.camera.position + l * 1e4f, 1.0f);
  const glm::vec2 ndc = c.w > 0.0f ? glm::vec2(c) / c.w : glm::vec2(0.0f);
  p.sun_screen = glm::vec4(ndc * 0.5f + 0.5f, c.w > 0.0f ? 1.0f : 0.0f, float(std::max(in.samples, 1u)));
  p.mie = glm::vec4(in.mie_g, in.strength, in.haze_density, in.haze_falloff);
  p.sun_color = glm::vec4(in.sun_color, in.decay);
  p.misc = glm::vec4(in.sky_distance_m, in.darkest, in.blur_length, 0.0f);
  const gpu::Buffer& ubo = ubo_[in.slot % gpu::kFramesInFlight];
  std::memcpy(ubo.mapped(), &p, sizeof p);
  const VkBuffer ubo_h = ubo.handle();

  const bool have_sky = sky_color.valid();
  TextureHandle sky = sky_color;
  if (!have_sky)
    sky = graph.import_texture("clouds.light_shafts.no_sky", TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, 1, 1),
                               white_.handle(), white_.view(), ResourceState::shader_read_only());
  TextureHandle shafts = graph.create_texture("clouds.light_shafts", TextureDesc::relative(VK_FORMAT_R16_SFLOAT, in.resolution_scale));
  const TextureHandle color = clouds.color, cdepth = clouds.depth;
  LightShafts* self = this;
  graph.add_pass("clouds.light_shafts", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(depth, Usage::Sampled);
        b.read(color, Usage::Sampled);
        b.read(sky, Usage::Sampled);
        shafts = b.write(shafts, Usage::StorageWrite);
      },
      [self, ubo_h, depth, color, sky, shafts](PassContext& c) {
        gpu::Pipeline& pipe = *self->shafts_;
        pipe.bind(c.cmd());
        gpu::DescriptorWriter()
            .uniform_buffer(SHAFT_BINDING_PARAMS, ubo_h, 0, sizeof(shared::CloudShaftParams))
            .sampled_image(SHAFT_BINDING_DEPTH, c.view(depth), self->nearest_, c.layout(depth))
            .sampled_image(SHAFT_BINDING_CLOUDS, c.view(color), self->linear_, c.layout(color))
            .sampled_image(SHAFT_BINDING_SKY, c.view(sky), self->linear_, c.layout(sky))
            .storage_image(SHAFT_BINDING_OUT, c.view(shafts))
            .push(self->ctx_, c.cmd(), pipe);
        const VkExtent3D e = c.extent(shafts);
        pipe.dispatch_threads(c.cmd(), e.width, e.height);
      });
  graph.add_pass("clouds.light_shafts_apply", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(depth, Usage::Sampled);
        b.read(color, Usage::Sampled);
        b.read(cdepth, Usage::Sampled);
        b.read(shafts, Usage::Sampled);
        hdr = b.read_write(hdr, Usage::StorageWrite);
      },
      [self, ubo_h, depth, color, cdepth, shafts, hdr](PassContext& c) {
        gpu::Pipeline& pipe = *self->apply_;
        pipe.bind(c.cmd());
        gpu::DescriptorWriter()
            .uniform_buffer(SHAFT_BINDING_PARAMS, ubo_h, 0, sizeof(shared::CloudShaftParams))
            .sampled_image(SHAFT_BINDING_DEPTH, c.view(depth), self->nearest_, c.layout(depth))
            .sampled_image(SHAFT_BINDING_CLOUDS, c.view(color), self->nearest_, c.layout(color))
            .sampled_image(SHAFT_BINDING_CLOUD_DEPTH, c.view(cdepth), self->nearest_, c.layout(cdepth))
            .sampled_image(SHAFT_BINDING_SHAFTS, c.view(shafts), self->linear_, c.layout(shafts))
            .storage_image(SHAFT_BINDING_HDR, c.view(hdr))
            .push(self->ctx_, c.cmd(), pipe);
        const VkExtent3D e = c.extent(hdr);
        shared::CloudMarchPush pc{};
        pc.target = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
        pipe.push_constants(c.cmd(), pc);
        pipe.dispatch_threads(c.cmd(), e.width, e.height);
      });
  return hdr;
}

}  // namespace cumulo::clouds::render
