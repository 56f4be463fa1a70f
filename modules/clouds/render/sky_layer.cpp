#include "modules/clouds/render/sky_layer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "engine/core/error.h"
#include "engine/core/png.h"
#include "engine/gpu/barrier.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/frames.h"
#include "engine/gpu/image.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "engine/render/history.h"
#include "modules/clouds/noise/noise.h"
#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/render/point_probe.h"
#include "modules/clouds/render/reconstruct_pass.h"
#include "modules/clouds/volume/volume_file.h"
#include "shaders/shared/cloud_params.h"
#include "shaders/shared/sky_layer_params.h"

namespace cumulo::clouds::render {
namespace fs = std::filesystem;
using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::TextureDesc;
using cumulo::render::TextureHandle;
using cumulo::render::Usage;

namespace {

TextureDesc texture_desc_3d(const gpu::Image& img) {
  const VkExtent3D e = img.extent();
  TextureDesc d = TextureDesc::absolute(img.format(), e.width, e.height, e.depth);
  d.type = cumulo::render::ImageType::Image3D;
  d.mips = img.mips();
  return d;
}

}  // namespace

CloudMapImage make_cloud_map(const weather::CloudMapSource& src, uint32_t n) {
  CloudMapImage m;
  // The largest features are scale_km across; a tile holds 4 of them (period 4 of the fBm).
  m.tile_m = 4.0f * std::max(src.scale_km, 0.1f) * 1000.0f;
  if (src.painted && src.painted->width > 0 && src.painted->rgba.size() == size_t(src.painted->width) * src.painted->height * 4) {
    m.width = src.painted->width, m.height = src.painted->height;
    m.rgba = src.painted->rgba;
    return m;
  }
  if (!src.png.empty()) {
    ImageRgba8 img = read_png_rgba8(src.png);
    m.width = img.width, m.height = img.height;
    m.rgba = std::move(img.rgba);
    return m;
  }
  m.width = m.height = n;
  m.rgba.resize(size_t(n) * n * 4);
  const uint32_t seed = derive_seed(src.seed, 0x5c1a0u);
  const int octaves = int(std::clamp(src.octaves, 1u, 8u));
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const glm::vec3 p(4.0f * float(x) / float(n), 4.0f * float(y) / float(n), 0.5f);
      // Coverage varies most; precipitation gathers in a few cells; type drifts slowly.
      const float c = perlin_fbm(p, 4, octaves, seed);
      const float r = perlin_fbm(p + glm::vec3(1.7f, 9.2f, 0.0f), 4, octaves, seed + 1);
      const float t = perlin_fbm(p + glm::vec3(5.3f, 2.1f, 0.0f), 4, std::max(1, octaves - 1), seed + 2);
      auto u8 = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
      uint8_t* px = &m.rgba[(size_t(y) * n + x) * 4];
      px[0] = u8(0.5f + 0.9f * c);
      px[1] = u8(0.5f + 1.2f * r);
      px[2] = u8(0.5f + 0.6f * t);
      px[3] = 255;
    }
  return m;
}

struct SkyLayer::Impl {
  gpu::Context& ctx;
  gpu::Image base, detail, curl;
  gpu::Image map_image;
  std::vector<std::pair<uint64_t, gpu::Image>> retired_maps;  // (frame replaced, image)
  weather::CloudMapSource map_source;
  bool map_loaded = false;
  float map_tile_m = 32000.0f;
  gpu::Pipeline* march = nullptr;
  gpu::Pipeline* march_occluded = nullptr;  // VOXEL_OCCLUSION 1: not marched where the voxel clouds hide it
  gpu::Pipeline* reconstruct = nullptr;
  gpu::Pipeline* probe = nullptr;  // built on first use
  gpu::PipelineLibrary& library;
  gpu::Buffer ubo[gpu::kFramesInFlight];
  gpu::Buffer recon_ubo[gpu::kFramesInFlight];  // reconstruct.comp reads CloudParams' camera fields
  cumulo::render::GpuHistory history{"clouds.sky_layer.history", VK_FORMAT_R16G16B16A16_SFLOAT, 0.5f,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  glm::mat4 prev_view_proj{1.0f};
  glm::vec3 last_camera{0.0f};
  bool have_last = false;
  VkSampler linear_clamp = VK_NULL_HANDLE, linear_repeat = VK_NULL_HANDLE, nearest_clamp = VK_NULL_HANDLE;

  Impl(gpu::Context& c, gpu::PipelineLibrary& l) : ctx(c), library(l) {}

  // Where the layer begins for this camera (SkyLayerFrame::near_fade_m): the whole distance inside the shell, shrinking to
  // 0 as the camera leaves it by as much (no step at its boundary); altitude over the planet under the world origin.
  static float near_fade(const SkyLayerFrame& sky, glm::vec3 camera) {
    const float fade = std::max(sky.near_fade_m, 0.0f);
    if (fade <= 0.0f) return 0.0f;
    const double r = double(sky.planet_radius_m);
    const float altitude = float(glm::length(glm::dvec3(camera) + glm::dvec3(0.0, r, 0.0)) - r);
    const float outside = std::max({sky.bottom_m - altitude, altitude - sky.top_m, 0.0f});
    return fade * std::clamp(1.0f - outside / fade, 0.0f, 1.0f);
  }

  // This frame's parameter block (camera, sun, weather, wind, the yield boxes of `in`'s instances).
  shared::SkyLayerParams params(const SkyLayerFrame& sky, const CloudFrameInputs& in) const {
    const CloudSettings& s = in.settings;
    const double t = in.time;

    shared::SkyLayerParams p{};
    p.inv_view_proj = in.camera.inv_view_proj;
    p.camera_pos = glm::vec4(in.camera.position, float(t));
    p.sun_dir = glm::vec4(glm::normalize(in.sun_direction), near_fade(sky, in.camera.position));
    p.sun_color = glm::vec4(in.sun_color, 0.0f);
    p.ambient_color = glm::vec4(in.ambient_color, 0.0f);
    p.shell =
        glm::vec4(sky.bottom_m, std::max(sky.top_m, sky.bottom_m + 1.0f), sky.planet_radius_m, sky.draw_distance_m);
    p.weather = glm::vec4(std::clamp(sky.coverage, 0.0f, 1.0f), std::clamp(sky.cloud_type, 0.0f, 1.0f),
                          std::clamp(sky.precipitation, 0.0f, 1.0f), std::clamp(sky.anvil_bias, 0.0f, 1.0f));
    const float wl = glm::length(sky.wind_direction);
    const glm::vec3 wind = wl > 0.0f ? sky.wind_direction / wl : glm::vec3(1.0f, 0.0f, 0.0f);
    // Drift and scroll wrap at a multiple of their tiles, so float precision holds over hours.
    const double travelled = double(sky.wind_speed) * t;
    const float drift = float(std::fmod(travelled, double(map_tile_m) * 64.0));
    p.wind = glm::vec4(wind.x * drift, wind.z * drift, std::clamp(sky.height_skew, 0.0f, 1.0f),
                       float(std::fmod(travelled * 0.5, 6000.0 * 64.0)));
    p.wind_dir = glm::vec4(wind, map_tile_m);
    p.shape = glm::vec4(6000.0f, 700.0f, 180.0f, 0.35f);
    p.horizon = glm::vec4(sky.horizon_bias_start_m, sky.draw_distance_m, sky.horizon_coverage, 1.0f);
    p.march =
        glm::vec4(s.extinction * sky.extinction_scale, 64.0f, 128.0f, 120.0f);  // 2015: 64 up .. 128 at the horizon
    p.phase = glm::vec4(s.hg_forward, s.hg_backward, s.hg_forward_weight, s.ms_strength);
    p.high = glm::vec4(std::clamp(sky.high_coverage, 0.0f, 1.0f), sky.high_altitude_m, 24000.0f, 0.8f);
    const float cirrus = float(std::fmod(travelled * 3.0, 24000.0 * 64.0)),
                alto = float(std::fmod(travelled * 1.5, 24000.0 * 64.0));
    p.high_scroll = glm::vec4(wind.x * cirrus, wind.z * cirrus, -wind.z * alto, wind.x * alto);  // alto at right angles
    uint32_t boxes = 0;
    for (const CloudInstance& inst : in.instances) {
      if (boxes == SKY_MAX_YIELD_BOXES) break;
      glm::vec3 lo, hi;
      instance_world_bounds(inst, lo, hi);
      p.yield_min[boxes] = glm::vec4(lo, 0.0f);
      p.yield_max[boxes] = glm::vec4(hi, 0.0f);
      ++boxes;
    }
    p.misc = glm::vec4(std::max(sky.yield_fade_m, 1.0f), float(boxes), float(in.frame_index % 64),
                       std::max(sky.yield_fade_vertical_m, 1.0f));
    return p;
  }

  gpu::Image load(const fs::path& file) {
    const Volume v = load_volume(file);
    if (v.encoding != VolumeEncoding::RGBA8)
      fail("%s: encoding %s; the 2.5D sky samples RGBA8 noise", file.string().c_str(), encoding_name(v.encoding));
    return upload_volume(ctx, v, VK_FORMAT_R8G8B8A8_UNORM, file);
  }

  // The weather's map on the GPU; re-made when the source changes. A PNG that fails keeps the last map.
  void ensure_map(const weather::CloudMapSource& src, uint64_t frame = 0) {
    // Maps replaced while the editor paints: frames in flight may still sample them.
    while (!retired_maps.empty() && retired_maps.front().first + gpu::kFramesInFlight + 1 <= frame)
      retired_maps.erase(retired_maps.begin());
    if (map_loaded && src == map_source) return;
    CloudMapImage m;
    try {
      m = make_cloud_map(src);
    } catch (const Error& e) {
      if (map_loaded) {
        std::fprintf(stderr, "cumulo: the 2.5D sky keeps its last cloud map: %s\n", e.what());
        map_source = src;  // do not retry every frame
        return;
      }
      throw;
    }
    if (map_loaded) {
      if (frame > 0) retired_maps.emplace_back(frame, std::move(map_image));
      else ctx.wait_idle();  // no frame count (a probe): frames in flight may sample the old map
    }
    map_image = gpu::Image(ctx, gpu::ImageDesc::tex2d(m.width, m.height, VK_FORMAT_R8G8B8A8_UNORM,
                                                      VK_IMAGE_USAGE_SAMPLED_BIT, 1, "clouds.sky_layer.cloud_map"));
    map_image.upload({{m.rgba.data(), m.rgba.size()}});
    map_tile_m = m.tile_m;
    map_source = src;
    map_loaded = true;
  }
};

SkyLayer::SkyLayer(gpu::Context& ctx, gpu::PipelineLibrary& library, const fs::path& dir)
    : impl_(std::make_unique<Impl>(ctx, library)) {
  Impl& m = *impl_;
  m.base = m.load(dir / "sky_noise_base.nvdf");
  m.detail = m.load(dir / "sky_noise_detail.nvdf");
  m.curl = m.load(dir / "curl_noise.nvdf");
  m.march = &library.compute({.shader = "clouds/sky_layer.comp", .name = "clouds.sky_layer"});
  m.march_occluded = &library.compute({.shader = "clouds/sky_layer.comp",
                                       .defines = {{"VOXEL_OCCLUSION", "1"}},
                                       .name = "clouds.sky_layer (voxel occlusion)"});
  m.reconstruct = &library.compute({.shader = "clouds/reconstruct.comp", .name = "clouds.sky_layer_reconstruct"});
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i) {
    m.ubo[i] = gpu::Buffer(ctx, {sizeof(shared::SkyLayerParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 gpu::MemoryUsage::Dynamic, "clouds.sky_layer.params"});
    m.recon_ubo[i] = gpu::Buffer(ctx, {sizeof(shared::CloudParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                       gpu::MemoryUsage::Dynamic, "clouds.sky_layer.camera"});
  }
  m.linear_clamp = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  m.linear_repeat = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
  m.nearest_clamp = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
}

SkyLayer::~SkyLayer() {
  if (impl_) impl_->ctx.wait_idle();
}

uint64_t SkyLayer::gpu_bytes() const {
  auto bytes = [](const gpu::Image& i) {
    return i ? uint64_t(i.extent().width) * i.extent().height * i.extent().depth * 4 : 0ull;
  };
  return bytes(impl_->base) + bytes(impl_->detail) + bytes(impl_->curl) + bytes(impl_->map_image);
}

std::vector<float> SkyLayer::probe_density(const SkyLayerFrame& sky, const CloudFrameInputs& in,
                                           const std::vector<glm::vec3>& points) {
  Impl& m = *impl_;
  if (points.empty()) return {};
  m.ensure_map(sky.map);
  if (!m.probe)
    m.probe = &m.library.compute({.shader = "clouds/sky_layer_probe.comp", .name = "clouds.sky_layer_probe"});
  const shared::SkyLayerParams p = m.params(sky, in);
  gpu::Buffer ubo(m.ctx, {sizeof p, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic, "sky probe params"});
  std::memcpy(ubo.mapped(), &p, sizeof p);
  const std::vector<uint8_t> bytes =
      run_point_probe(m.ctx, *m.probe, points, sizeof(float), SKY_BINDING_PROBE_POINTS, SKY_BINDING_PROBE_OUT,
                      [&](gpu::DescriptorWriter& w) {
                        w.uniform_buffer(SKY_BINDING_PARAMS, ubo.handle(), 0, sizeof p)
                            .sampled_image(SKY_BINDING_CLOUD_MAP, m.map_image.view(), m.linear_repeat)
                            .sampled_image(SKY_BINDING_BASE_NOISE, m.base.view(), m.linear_repeat)
                            .sampled_image(SKY_BINDING_DETAIL_NOISE, m.detail.view(), m.linear_repeat)
                            .sampled_image(SKY_BINDING_CURL, m.curl.view(), m.linear_repeat);
                      });
  std::vector<float> out(points.size());
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

SkyLayer::Outputs SkyLayer::add_passes(cumulo::render::RenderGraph& graph, const SkyLayerFrame& sky,
                                       const CloudFrameInputs& in, TextureHandle scene_depth, const CloudPassOutputs& voxel) {
  Impl& m = *impl_;
  m.ensure_map(sky.map, in.frame_index + 1);
  const CloudSettings& s = in.settings;
  const double t = in.time;
  shared::SkyLayerParams p = m.params(sky, in);
  p.prev_view_proj = m.prev_view_proj;  // before it becomes this frame's below
  const gpu::Buffer& ubo = m.ubo[in.slot % gpu::kFramesInFlight];
  std::memcpy(ubo.mapped(), &p, sizeof p);

  shared::CloudParams cp{};
  cp.inv_view_proj = in.camera.inv_view_proj;
  cp.view_proj = in.camera.view_proj;
  cp.prev_view_proj = m.prev_view_proj;
  cp.camera_pos = glm::vec4(in.camera.position, float(t));
  const gpu::Buffer& recon_ubo = m.recon_ubo[in.slot % gpu::kFramesInFlight];
  std::memcpy(recon_ubo.mapped(), &cp, sizeof cp);
  m.prev_view_proj = in.camera.view_proj;

  // Half resolution, times the frame's resolution scale (dynamic resolution; a new scale replaces the history).
  const float scale = 0.5f * in.resolution_scale;
  if (in.camera_cut || !s.temporal) m.history.invalidate();
  m.history.set_scale(scale);
  const cumulo::render::HistoryHandles h = m.history.import(m.ctx, graph);

  // One pixel of each 4x4 block of the half-resolution target per frame, in Bayer order.
  constexpr uint32_t kBlock = 4;
  const glm::uvec2 offset = s.temporal ? reprojection_offset(kBlock, in.frame_index) : glm::uvec2(0, 0);
  const VkExtent2D half = cumulo::render::relative_extent(graph.output_size(), scale);
  const uint32_t hw = half.width, hh = half.height;
  const uint32_t sw = (hw + kBlock - 1) / kBlock, sh = (hh + kBlock - 1) / kBlock;
  TextureHandle sub_c =
      graph.create_texture("clouds.sky_layer.sub_color", TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, sw, sh));
  TextureHandle sub_d =
      graph.create_texture("clouds.sky_layer.sub_depth", TextureDesc::absolute(VK_FORMAT_R32G32B32A32_SFLOAT, sw, sh));
  TextureHandle out_d =
      graph.create_texture("clouds.sky_layer.depth", TextureDesc::relative(VK_FORMAT_R32G32B32A32_SFLOAT, scale));
  TextureHandle base = graph.import_texture("clouds.sky_layer.base_noise", texture_desc_3d(m.base), m.base.handle(),
                                            m.base.view(), cumulo::render::ResourceState::shader_read_only());
  TextureHandle detail =
      graph.import_texture("clouds.sky_layer.detail_noise", texture_desc_3d(m.detail), m.detail.handle(),
                           m.detail.view(), cumulo::render::ResourceState::shader_read_only());
  TextureHandle curl = graph.import_texture("clouds.sky_layer.curl", texture_desc_3d(m.curl), m.curl.handle(),
                                            m.curl.view(), cumulo::render::ResourceState::shader_read_only());
  const VkExtent3D me = m.map_image.extent();
  TextureHandle map = graph.import_texture(
      "clouds.sky_layer.cloud_map", TextureDesc::absolute(VK_FORMAT_R8G8B8A8_UNORM, me.width, me.height),
      m.map_image.handle(), m.map_image.view(), cumulo::render::ResourceState::shader_read_only());
  Impl* mp = &m;
  const VkBuffer ubo_h = ubo.handle();
  const bool occlusion = voxel.color.valid() && voxel.depth.valid();
  const TextureHandle voxel_color = voxel.color, voxel_depth = voxel.depth, history_prev = h.previous;
  const bool history_valid = h.valid;
  graph.add_pass(
      "clouds.sky_layer", Queue::Compute,
      [&](PassBuilder& b) {
        if (occlusion) {
          b.read(voxel_color, Usage::Sampled);
          b.read(voxel_depth, Usage::Sampled);
          b.read(history_prev, Usage::Sampled);
        }
        b.read(map, Usage::Sampled);
        b.read(base, Usage::Sampled);
        b.read(detail, Usage::Sampled);
        b.read(curl, Usage::Sampled);
        b.read(scene_depth, Usage::Sampled);
        sub_c = b.write(sub_c, Usage::StorageWrite);
        sub_d = b.write(sub_d, Usage::StorageWrite);
      },
      [mp, ubo_h, map, base, detail, curl, scene_depth, sub_c, sub_d, hw, hh, offset, occlusion, voxel_color, voxel_depth,
       history_prev, history_valid](PassContext& c) {
        gpu::Pipeline& pipe = occlusion ? *mp->march_occluded : *mp->march;
        pipe.bind(c.cmd());
        gpu::DescriptorWriter w;
        if (occlusion)
          w.sampled_image(SKY_BINDING_VOXEL_COLOR, c.view(voxel_color), mp->linear_clamp, c.layout(voxel_color))
              .sampled_image(SKY_BINDING_VOXEL_DEPTH, c.view(voxel_depth), mp->linear_clamp, c.layout(voxel_depth))
              .sampled_image(SKY_BINDING_HISTORY, c.view(history_prev), mp->linear_clamp, c.layout(history_prev));
        w
            .uniform_buffer(SKY_BINDING_PARAMS, ubo_h, 0, sizeof(shared::SkyLayerParams))
            .sampled_image(SKY_BINDING_CLOUD_MAP, c.view(map), mp->linear_repeat, c.layout(map))
            .sampled_image(SKY_BINDING_BASE_NOISE, c.view(base), mp->linear_repeat, c.layout(base))
            .sampled_image(SKY_BINDING_DETAIL_NOISE, c.view(detail), mp->linear_repeat, c.layout(detail))
            .sampled_image(SKY_BINDING_CURL, c.view(curl), mp->linear_repeat, c.layout(curl))
            .sampled_image(SKY_BINDING_SCENE_DEPTH, c.view(scene_depth), mp->nearest_clamp, c.layout(scene_depth))
            .storage_image(SKY_BINDING_OUT_COLOR, c.view(sub_c))
            .storage_image(SKY_BINDING_OUT_DEPTH, c.view(sub_d))
            .push(mp->ctx, c.cmd(), pipe);
        shared::CloudMarchPush pc{};
        pc.target = glm::vec4(float(hw), float(hh), 1.0f / float(hw), 1.0f / float(hh));
        pc.sub = glm::vec4(float(kBlock), float(offset.x), float(offset.y), history_valid ? 1.0f : 0.0f);
        pipe.push_constants(c.cmd(), pc);
        const VkExtent3D e = c.extent(sub_c);
        pipe.dispatch_threads(c.cmd(), e.width, e.height);
      });
  TextureHandle next = h.current;
  add_reconstruct_pass(graph, m.ctx, "clouds.sky_layer_reconstruct",
                       {m.reconstruct, recon_ubo.handle(), sub_c, sub_d, h.previous, scene_depth, kBlock, offset, h.valid}, next,
                       out_d);
  return {next, out_d};
}

}  // namespace cumulo::clouds::render
