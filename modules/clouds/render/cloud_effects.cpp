#include "modules/clouds/render/cloud_effects.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "engine/scene/model.h"
#include "shaders/shared/cloud_params.h"

namespace cumulo::clouds::render {

using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::TextureHandle;
using cumulo::render::Usage;

namespace {

constexpr float kBoltCoreRadius = 1.5f;  // m: a return stroke's luminous channel is a few cm, its glow metres

// The bolts' screen rectangle (pixels, with a margin for the glow); the whole screen when a segment
// crosses behind the camera.
glm::ivec4 bolt_rect(const shared::CloudEffectsParams& p, uint32_t count, const scene::CameraView& cam, VkExtent2D size) {
  // The margin covers the glow: 150 m (where it has faded to nothing) at the nearest endpoint's distance.
  glm::vec2 lo(1e9f), hi(-1e9f);
  float nearest = 1e30f;
  for (uint32_t i = 0; i < count; ++i)
    for (const glm::vec4& e : {p.seg_a[i], p.seg_b[i]}) {
      const glm::vec4 c = cam.project(glm::vec3(e));
      if (c.w <= 0.0f) return {0, 0, int(size.width), int(size.height)};
      const glm::vec2 px = (glm::vec2(c) * 0.5f + 0.5f) * glm::vec2(size.width, size.height);
      lo = glm::min(lo, px), hi = glm::max(hi, px);
      nearest = std::min(nearest, glm::distance(glm::vec3(e), cam.position));
    }
  const float margin = std::min(4.0f + 150.0f / std::max(nearest * p.misc.x, 1e-6f), float(std::max(size.width, size.height)));
  const glm::ivec2 a = glm::clamp(glm::ivec2(glm::floor(lo - margin)), glm::ivec2(0), glm::ivec2(size.width, size.height));
  const glm::ivec2 b = glm::clamp(glm::ivec2(glm::ceil(hi + margin)), glm::ivec2(0), glm::ivec2(size.width, size.height));
  return {a.x, a.y, std::max(0, b.x - a.x), std::max(0, b.y - a.y)};
}

// The screen rectangle of the rain columns' bounding boxes (the whole screen when one reaches behind the
// camera; empty when none is in view).
glm::ivec4 rain_rect(const shared::CloudEffectsParams& p, uint32_t count, const scene::CameraView& cam, VkExtent2D size) {
  glm::vec2 lo(1e9f), hi(-1e9f);
  const scene::Frustum frustum = scene::Frustum::from(cam.view_proj);
  bool visible = false;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 c(p.rain_column[i]);
    const float r = p.rain_column[i].w, bottom = p.rain_params[i].y;
    scene::Bounds box;
    box.add({c.x - r, bottom, c.z - r});
    box.add({c.x + r, c.y, c.z + r});
    if (!frustum.intersects(box)) continue;  // off screen: no rain to draw for it
    visible = true;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner(c.x + ((k & 1) ? r : -r), (k & 2) ? c.y : bottom, c.z + ((k & 4) ? r : -r));
      const glm::vec4 q = cam.project(corner);
      if (q.w <= 0.0f) return {0, 0, int(size.width), int(size.height)};
      const glm::vec2 px = (glm::vec2(q) * 0.5f + 0.5f) * glm::vec2(size.width, size.height);
      lo = glm::min(lo, px), hi = glm::max(hi, px);
    }
  }
  if (!visible) return {0, 0, 0, 0};
  const glm::ivec2 a = glm::clamp(glm::ivec2(glm::floor(lo)) - 1, glm::ivec2(0), glm::ivec2(size.width, size.height));
  const glm::ivec2 b = glm::clamp(glm::ivec2(glm::ceil(hi)) + 1, glm::ivec2(0), glm::ivec2(size.width, size.height));
  return {a.x, a.y, std::max(0, b.x - a.x), std::max(0, b.y - a.y)};
}

}  // namespace

CloudEffects::CloudEffects(gpu::Context& ctx, gpu::PipelineLibrary& library) : ctx_(ctx) {
  bolt_ = &library.compute({.shader = "clouds/lightning_bolt.comp", .name = "clouds.lightning_bolt"});
  rain_ = &library.compute({.shader = "clouds/rain.comp", .name = "clouds.rain"});
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    ubo_[i] = gpu::Buffer(ctx, {sizeof(shared::CloudEffectsParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                gpu::MemoryUsage::Dynamic, i ? "clouds.effects.1" : "clouds.effects.0"});
  nearest_ = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
}

TextureHandle CloudEffects::add_passes(cumulo::render::RenderGraph& graph, const CloudEffectsInputs& in, TextureHandle hdr,
                                       TextureHandle depth, const CloudPassOutputs& clouds) {
  if (in.bolts.empty() && in.rain.empty()) return hdr;
  const VkExtent2D size = graph.output_size();
  shared::CloudEffectsParams p{};
  p.inv_view_proj = in.camera.inv_view_proj;
  p.camera_pos = glm::vec4(in.camera.position, float(in.time));
  p.viewport = glm::vec4(float(size.width), float(size.height), 1.0f / float(size.width), 1.0f / float(size.height));
  p.bolt = glm::vec4(in.bolt_color, kBoltCoreRadius);
  const bool have_clouds = clouds.color.valid() && clouds.depth.valid();
  p.misc = glm::vec4(2.0f * std::tan(0.5f * in.camera.fov_y) / float(size.height), have_clouds ? 1.0f : 0.0f, 0.0f, 0.0f);
  // The two brightest bolts; a segment's brightness carries its bolt's intensity (the shader sums them).
  std::vector<const BoltFrame*> bolts;
  for (const BoltFrame& b : in.bolts) bolts.push_back(&b);
  std::sort(bolts.begin(), bolts.end(), [](const BoltFrame* a, const BoltFrame* b) { return a->intensity > b->intensity; });
  uint32_t segs = 0;
  for (size_t k = 0; k < bolts.size() && k < 2; ++k)
    for (const BoltSegmentFrame& s : bolts[k]->segments) {
      if (segs == CLOUD_MAX_BOLT_SEGMENTS) break;
      p.seg_a[segs] = glm::vec4(s.a, s.brightness * bolts[k]->intensity);
      p.seg_b[segs] = glm::vec4(s.b, 0.0f);
      ++segs;
    }
  uint32_t rain = 0;
  for (const RainColumn& r : in.rain) {
    if (rain == CLOUD_MAX_RAIN || !(r.intensity > 0.0f) || !(r.radius > 0.0f)) continue;
    p.rain_column[rain] = glm::vec4(r.base_center, r.radius);
    p.rain_params[rain] = glm::vec4(std::min(r.intensity, 1.0f), r.bottom, 0.0f, 0.0f);
    ++rain;
  }
  p.rain_light = glm::vec4(in.rain_light, 0.0f);
  p.counts = glm::uvec4(segs, rain, 0, 0);
  const gpu::Buffer& ubo = ubo_[in.slot % gpu::kFramesInFlight];
  std::memcpy(ubo.mapped(), &p, sizeof p);
  const VkBuffer ubo_handle = ubo.handle();
  // Without cloud passes the shaders read the scene depth in the cloud slots (never used: misc.y = 0).
  const TextureHandle ccolor = have_clouds ? clouds.color : depth, cdepth = have_clouds ? clouds.depth : depth;
  gpu::Context* ctx = &ctx_;
  const VkSampler nearest = nearest_;

  auto add = [&](const char* name, gpu::Pipeline* pipe, glm::ivec4 rect) {
    if (rect.z <= 0 || rect.w <= 0) return;
    graph.add_pass(name, Queue::Compute,
        [&](PassBuilder& b) {
          b.read(depth, Usage::Sampled);
          if (have_clouds) {
            b.read(ccolor, Usage::Sampled);
            b.read(cdepth, Usage::Sampled);
          }
          hdr = b.read_write(hdr, Usage::StorageWrite);
        },
        [ctx, pipe, ubo_handle, depth, ccolor, cdepth, hdr, rect, nearest](PassContext& c) {
          gpu::DescriptorWriter w;
          w.uniform_buffer(CLOUD_BINDING_FX_PARAMS, ubo_handle, 0, sizeof(shared::CloudEffectsParams))
              .sampled_image(CLOUD_BINDING_FX_DEPTH, c.view(depth), nearest, c.layout(depth))
              .sampled_image(CLOUD_BINDING_FX_CLOUDS, c.view(ccolor), nearest, c.layout(ccolor))
              .sampled_image(CLOUD_BINDING_FX_CLOUD_DEPTH, c.view(cdepth), nearest, c.layout(cdepth))
              .storage_image(CLOUD_BINDING_FX_HDR, c.view(hdr));
          pipe->bind(c.cmd());
          w.push(*ctx, c.cmd(), *pipe);
          shared::CloudEffectsPush pc{rect};
          pipe->push_constants(c.cmd(), pc);
          pipe->dispatch_threads(c.cmd(), uint32_t(rect.z), uint32_t(rect.w));
        });
  };
  if (segs > 0) add("clouds.lightning_bolt", bolt_, bolt_rect(p, segs, in.camera, size));
  if (rain > 0) add("clouds.rain", rain_, rain_rect(p, rain, in.camera, size));
  return hdr;
}

}  // namespace cumulo::clouds::render
