#include "modules/clouds/render/envelope_layer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "engine/core/error.h"
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
#include "modules/clouds/render/cloud_assets.h"
#include "modules/clouds/render/point_probe.h"
#include "modules/clouds/render/reconstruct_pass.h"
#include "modules/clouds/volume/volume_file.h"
#include "shaders/shared/cloud_params.h"
#include "shaders/shared/envelope_params.h"

namespace cumulo::clouds::render {
namespace fs = std::filesystem;
using cumulo::render::PassBuilder;
using cumulo::render::PassContext;
using cumulo::render::Queue;
using cumulo::render::TextureDesc;
using cumulo::render::TextureHandle;
using cumulo::render::Usage;

namespace {

// The terrain hides the sun from the envelope this frame (the march's light depth; else its stand-in).
bool terrain_shadowed(const CloudFrameInputs& in) { return in.settings.terrain_shadow && in.terrain_depth.valid(); }

TextureDesc texture_desc(const gpu::Image& img) {
  const VkExtent3D e = img.extent();
  TextureDesc d = TextureDesc::absolute(img.format(), e.width, e.height, e.depth);
  if (e.depth > 1) d.type = cumulo::render::ImageType::Image3D;
  d.mips = img.mips();
  return d;
}

// The ambient at the envelope's bottom, as a share of the top's (the 2.5D sky's 0.35: bases see less sky).
constexpr float kAmbientBottom = 0.35f;
// With the slab lighting: Wrenninge's octaves a, b (extinction, contribution per octave), measured on the envelope's
// calibration views (docs/fidelity/envelope_lighting.md); their eccentricity c is a setting (envelope_eccentricity).
constexpr float kOctaveExtinction = 0.5f, kOctaveContribution = 0.7f;

}  // namespace

float detail_mean_fbm(const Volume& detail) {
  if (detail.levels.empty() || detail.encoding != VolumeEncoding::RGBA8) return 0.0f;
  const std::vector<uint8_t>& t = detail.levels[0];
  double sum = 0.0;
  for (size_t i = 0; i + 3 < t.size(); i += 4) sum += 0.625 * t[i] + 0.25 * t[i + 1] + 0.125 * t[i + 2];
  const size_t texels = t.size() / 4;
  return texels ? float(sum / (255.0 * double(texels))) : 0.0f;
}

uint32_t envelope_block_for_device(bool cpu_device, bool split) { return cpu_device ? (split ? 4u : 2u) : 1u; }

bool envelope_within(const envelope::EnvelopeMaps& e, glm::vec3 p, float distance) {
  const float d2 = distance * distance;
  for (uint32_t j = 0; j < e.resolution; ++j) {
    const float z0 = e.origin.y + float(j) * e.texel_m, dz = std::max({z0 - p.z, p.z - (z0 + e.texel_m), 0.0f});
    if (dz * dz >= d2) continue;
    for (uint32_t i = 0; i < e.resolution; ++i) {
      const glm::vec4& s = e.steps[size_t(j) * e.resolution + i];
      if (!(s.x > envelope::kEmptyTop)) continue;  // no envelope in this texel's column
      const float x0 = e.origin.x + float(i) * e.texel_m;
      const float dx = std::max({x0 - p.x, p.x - (x0 + e.texel_m), 0.0f}), dy = std::max({s.y - p.y, p.y - s.x, 0.0f});
      if (dx * dx + dy * dy + dz * dz < d2) return true;
    }
  }
  return false;
}

struct EnvelopeLayer::Impl {
  gpu::Context& ctx;
  gpu::PipelineLibrary& library;
  gpu::Image base, detail;
  float detail_fbm = 0.0f;  // the detail noise's mean fBm (envelope_march.comp light_optical_depth's erosion)
  gpu::Image shape, steps, aux;
  std::shared_ptr<const envelope::EnvelopeMaps> maps;
  std::vector<std::pair<uint64_t, gpu::Image>> retired;  // (frame replaced, image)
  gpu::Pipeline* march_cone = nullptr;
  gpu::Pipeline* march_fixed = nullptr;
  // Bound in place of the voxel clouds' shadow map and the terrain's light depth when a frame has none (the march
  // reads both always: no variant compiled when one appears a few frames into a view). A transmittance of 1 and an
  // occluder at the far side hide nothing.
  gpu::Image no_voxel_shadow, no_light_depth;
  gpu::Pipeline* probe = nullptr;  // built on first use
  gpu::Buffer ubo[gpu::kFramesInFlight][3];  // [slot][near, far, the path tracer's medium]
  // The sub-sampled far pass's reprojection (EnvelopeMarchSettings::far_block > 1).
  gpu::Pipeline* reconstruct = nullptr;
  gpu::Pipeline* reconstruct_merge = nullptr;  // MERGE_NEAR: the split's near pass merged in
  gpu::Pipeline* reconstruct_near = nullptr;   // CLIP_TO_SPLIT: the split's near pass, sub-sampled
  cumulo::render::GpuHistory near_history{"clouds.envelope.near_history", VK_FORMAT_R16G16B16A16_SFLOAT, 0.5f,
                                          VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  gpu::Buffer recon_ubo[gpu::kFramesInFlight];  // reconstruct.comp reads CloudParams' camera fields
  cumulo::render::GpuHistory history{"clouds.envelope.history", VK_FORMAT_R16G16B16A16_SFLOAT, 1.0f,
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT};
  glm::mat4 prev_view_proj{1.0f};
  glm::vec3 box_lo{1e30f}, box_hi{-1e30f};  // the columns holding envelope (set_maps)
  // The shadow on the terrain (add_shadow_passes).
  gpu::Image terrain;  // R32F heights over the square [terrain_origin, + terrain_side]
  glm::vec2 terrain_origin{0.0f};
  float terrain_side = 0.0f;
  gpu::Pipeline* shadow_pipe = nullptr;   // built on first use
  gpu::Pipeline* combine_pipe = nullptr;
  gpu::Image env_shadow, combined_shadow;
  cumulo::render::PersistentTexture env_shadow_tex, combined_shadow_tex;
  gpu::Buffer shadow_ubo[gpu::kFramesInFlight];
  std::array<float, 11> shadow_key{};  // what the envelope's own map was marched for (NaN once its image is made: stale)
  std::array<float, 13> combined_key{};  // what the combined map was made of (the voxel map's version, both planes)
  glm::vec3 shadow_scroll{0.0f};
  uint32_t shadow_marches = 0;
  uint64_t shadow_frame = 0;  // the frame the envelope's map was last marched
  VkSampler linear_clamp = VK_NULL_HANDLE, linear_repeat = VK_NULL_HANDLE, nearest_clamp = VK_NULL_HANDLE;

  Impl(gpu::Context& c, gpu::PipelineLibrary& l) : ctx(c), library(l) {}

  gpu::Image load(const fs::path& file, float* mean_fbm = nullptr) {
    const Volume v = load_volume(file);
    if (v.encoding != VolumeEncoding::RGBA8)
      fail("%s: encoding %s; the envelope clouds sample RGBA8 noise", file.string().c_str(), encoding_name(v.encoding));
    if (mean_fbm) *mean_fbm = detail_mean_fbm(v);
    return upload_volume(ctx, v, VK_FORMAT_R8G8B8A8_UNORM, file);
  }

  shared::EnvelopeParams params(const EnvelopeDraw& draw, const EnvelopeMarchSettings& m, const CloudFrameInputs& in,
                                float segment_start, float segment_end) const {
    const envelope::EnvelopeMaps& e = *maps;
    const CloudSettings& s = in.settings;
    shared::EnvelopeParams p{};
    p.inv_view_proj = in.camera.inv_view_proj;
    p.camera_pos = glm::vec4(in.camera.position, float(in.time));
    p.sun_dir = glm::vec4(glm::normalize(in.sun_direction), s.ms_slab ? s.envelope_ms_diffused : 0.0f);
    p.sun_color = glm::vec4(in.sun_color, s.ms_slab ? s.ground_albedo : 0.0f);
    p.ambient_color = glm::vec4(in.ambient_color, 0.0f);
    // The slab presets (issue 21) light the envelope by octave_light; the others by issue 24's terms (x = 0).
    if (s.ms_slab) p.octaves = glm::vec4(kOctaveExtinction, kOctaveContribution, s.envelope_eccentricity, s.edge_depth_scale);
    p.map = glm::vec4(e.origin, e.texel_m, float(e.resolution));
    p.heights = glm::vec4(e.min_bottom, e.max_top, std::max(draw.edge_m, 1e-3f),
                          std::max(draw.density, 0.0f) * std::max(m.density_scale, 0.0f));
    p.noise = glm::vec4(std::max(m.noise_tile_m, 1.0f), std::max(m.detail_tile_m, 1.0f),
                        std::clamp(m.detail_erosion, 0.0f, 1.0f), std::clamp(draw.coverage, 0.0f, 1.0f));
    p.wind = glm::vec4(envelope::envelope_scroll(draw.wind_direction, draw.wind_speed, m.noise_tile_m, in.time),
                       s.extinction);
    p.march = glm::vec4(std::max(m.step_m, 0.5f), std::max(m.step_growth, 0.0f), float(std::max(m.max_steps, 1u)),
                        std::max(m.light_step_m, 1.0f));
    p.stepping = glm::vec4(m.cone_stepping ? 1.0f : 0.0f, m.draw_distance_m, std::clamp(s.albedo, 0.0f, 1.0f), segment_start);
    p.phase = glm::vec4(s.hg_forward, s.hg_backward, s.hg_forward_weight, s.ms_strength);
    uint32_t boxes = 0;
    for (const CloudInstance& inst : in.instances) {
      if (boxes == ENV_MAX_YIELD_BOXES) break;
      glm::vec3 lo, hi;
      instance_world_bounds(inst, lo, hi);
      p.yield_min[boxes] = glm::vec4(lo, 0.0f);
      p.yield_max[boxes] = glm::vec4(hi, 0.0f);
      ++boxes;
    }
    p.misc = glm::vec4(segment_end, kAmbientBottom, float(boxes), envelope::kYieldFadeM);
    // Without a map this frame the stand-ins are bound (add_passes); a depth range of 0 turns the terrain's shadow
    // off in data, not in a branch.
    p.light_depth = in.terrain_depth_matrix;
    p.terrain = glm::vec4(terrain_shadowed(in) ? in.terrain_depth_range_m : 0.0f, in.voxel_shadow.height,
                          s.ms_slab && s.envelope_light_erosion ? detail_fbm : 0.0f, 0.0f);
    p.voxel_shadow = glm::vec4(in.voxel_shadow.origin, in.voxel_shadow.size);
    p.ground_light = glm::vec4(ground_radiance(in), 0.0f);
    return p;
  }

  // What envelope_density.glsl reads (its parameter block `ubo` and the maps and noise), imported once per graph; the
  // shadow, the march and the path tracer's medium share it.
  CloudFrameInputs::EnvelopeMedium density_inputs(cumulo::render::RenderGraph& g, VkBuffer ubo) const {
    CloudFrameInputs::EnvelopeMedium d;
    d.params = ubo;
    d.shape = import(g, "clouds.envelope.shape", shape);
    d.steps = import(g, "clouds.envelope.steps", steps);
    d.aux = import(g, "clouds.envelope.aux", aux);
    d.base_noise = import(g, "clouds.envelope.base_noise", base);
    d.detail_noise = import(g, "clouds.envelope.detail_noise", detail);
    return d;
  }
  static void read_density(PassBuilder& b, const CloudFrameInputs::EnvelopeMedium& d) {
    for (TextureHandle t : {d.shape, d.steps, d.aux, d.base_noise, d.detail_noise}) b.read(t, Usage::Sampled);
  }
  gpu::DescriptorWriter& bind_density(gpu::DescriptorWriter& w, PassContext& c, const CloudFrameInputs::EnvelopeMedium& d) const {
    return w.uniform_buffer(ENV_BINDING_PARAMS, d.params, 0, sizeof(shared::EnvelopeParams))
        .sampled_image(ENV_BINDING_SHAPE, c.view(d.shape), linear_clamp, c.layout(d.shape))
        .sampled_image(ENV_BINDING_STEPS, c.view(d.steps), nearest_clamp, c.layout(d.steps))
        .sampled_image(ENV_BINDING_AUX, c.view(d.aux), linear_clamp, c.layout(d.aux))
        .sampled_image(ENV_BINDING_BASE_NOISE, c.view(d.base_noise), linear_repeat, c.layout(d.base_noise))
        .sampled_image(ENV_BINDING_DETAIL_NOISE, c.view(d.detail_noise), linear_repeat, c.layout(d.detail_noise));
  }

  // Once per graph (the shadow, the march and the path tracer's medium read the same maps in one frame).
  TextureHandle import(cumulo::render::RenderGraph& g, const char* name, const gpu::Image& img) const {
    if (const TextureHandle h = g.find_import(name, img.handle()); h.valid()) return h;
    return g.import_texture(name, texture_desc(img), img.handle(), img.view(), cumulo::render::ResourceState::shader_read_only());
  }
};

EnvelopeLayer::EnvelopeLayer(gpu::Context& ctx, gpu::PipelineLibrary& library, const fs::path& dir)
    : impl_(std::make_unique<Impl>(ctx, library)) {
  Impl& m = *impl_;
  m.base = m.load(dir / "sky_noise_base.nvdf");
  m.detail = m.load(dir / "sky_noise_detail.nvdf", &m.detail_fbm);
  m.march_cone = &library.compute({.shader = "clouds/envelope_march.comp",
                                   .defines = {{"CONE_STEPPING", "1"}},
                                   .name = "clouds.envelope (cone stepping)"});
  m.march_fixed = &library.compute({.shader = "clouds/envelope_march.comp",
                                    .defines = {{"CONE_STEPPING", "0"}},
                                    .name = "clouds.envelope (fixed steps)"});
  const uint16_t one = 0x3c00;  // 1.0 in half precision
  m.no_voxel_shadow = gpu::Image::single_texel(ctx, VK_FORMAT_R16_SFLOAT, &one, sizeof one, "clouds.envelope.no_voxel_shadow");
  const float far_side = 1.0f;
  m.no_light_depth = gpu::Image::single_texel(ctx, VK_FORMAT_R32_SFLOAT, &far_side, sizeof far_side,
                                              "clouds.envelope.no_light_depth");
  m.reconstruct = &library.compute({.shader = "clouds/reconstruct.comp", .name = "clouds.envelope_reconstruct"});
  m.reconstruct_merge = &library.compute({.shader = "clouds/reconstruct.comp",
                                          .defines = {{"MERGE_NEAR", "1"}},
                                          .name = "clouds.envelope_reconstruct (merge near)"});
  m.reconstruct_near = &library.compute({.shader = "clouds/reconstruct.comp",
                                         .defines = {{"CLIP_TO_SPLIT", "1"}},
                                         .name = "clouds.envelope_reconstruct (near)"});
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    m.recon_ubo[i] = gpu::Buffer(ctx, {sizeof(shared::CloudParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                       gpu::MemoryUsage::Dynamic, "clouds.envelope.camera"});
  for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
    for (uint32_t k = 0; k < 3; ++k)
      m.ubo[i][k] = gpu::Buffer(ctx, {sizeof(shared::EnvelopeParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                      gpu::MemoryUsage::Dynamic, "clouds.envelope.params"});
  m.linear_clamp = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
  m.linear_repeat = ctx.samplers().get(gpu::SamplerDesc::linear_repeat());
  m.nearest_clamp = ctx.samplers().get(gpu::SamplerDesc::nearest_clamp());
}

EnvelopeLayer::~EnvelopeLayer() {
  if (impl_) impl_->ctx.wait_idle();
}

bool EnvelopeLayer::has_maps() const { return impl_->maps && !impl_->maps->empty(); }

void EnvelopeLayer::set_maps(std::shared_ptr<const envelope::EnvelopeMaps> maps, uint64_t frame_index) {
  Impl& m = *impl_;
  while (!m.retired.empty() && m.retired.front().first + gpu::kFramesInFlight + 1 <= frame_index)
    m.retired.erase(m.retired.begin());
  if (!maps || maps->empty()) fail("envelope clouds: no baked maps to upload");
  const envelope::EnvelopeMaps& e = *maps;
  const size_t n = size_t(e.resolution) * e.resolution;
  if (e.shape.size() != n || e.steps.size() != n || e.distance_m.size() != n || e.edge_m.size() != n || e.apex.size() != n)
    fail("envelope clouds: the baked maps disagree on their size (%u texels a side)", e.resolution);
  if (m.shape) {
    if (frame_index > 0) {
      m.retired.emplace_back(frame_index, std::move(m.shape));
      m.retired.emplace_back(frame_index, std::move(m.steps));
      m.retired.emplace_back(frame_index, std::move(m.aux));
    } else {
      m.ctx.wait_idle();
    }
  }
  auto make = [&](VkFormat f, const char* name, const void* data, size_t bytes) {
    gpu::Image img(m.ctx, gpu::ImageDesc::tex2d(e.resolution, e.resolution, f, VK_IMAGE_USAGE_SAMPLED_BIT, 1, name));
    img.upload({{data, bytes}});
    return img;
  };
  m.shape = make(VK_FORMAT_R32G32B32A32_SFLOAT, "clouds.envelope.shape", e.shape.data(), n * sizeof(glm::vec4));
  m.steps = make(VK_FORMAT_R32G32B32A32_SFLOAT, "clouds.envelope.steps", e.steps.data(), n * sizeof(glm::vec4));
  std::vector<glm::vec4> aux(n);
  for (size_t i = 0; i < n; ++i) aux[i] = glm::vec4(e.distance_m[i], e.edge_m[i], e.apex[i]);
  m.aux = make(VK_FORMAT_R32G32B32A32_SFLOAT, "clouds.envelope.aux", aux.data(), n * sizeof(glm::vec4));
  // The clouds' tight box: the columns that hold any envelope (the frame passes are left out when it is off screen).
  m.box_lo = glm::vec3(1e30f), m.box_hi = glm::vec3(-1e30f);
  for (uint32_t j = 0; j < e.resolution; ++j)
    for (uint32_t i = 0; i < e.resolution; ++i) {
      const glm::vec4& st = e.steps[size_t(j) * e.resolution + i];
      if (!(st.x > envelope::kEmptyTop)) continue;
      const glm::vec3 lo(e.origin.x + float(i) * e.texel_m, st.y, e.origin.y + float(j) * e.texel_m);
      m.box_lo = glm::min(m.box_lo, lo);
      m.box_hi = glm::max(m.box_hi, glm::vec3(lo.x + e.texel_m, st.x, lo.z + e.texel_m));
    }
  m.maps = std::move(maps);
  m.shadow_key.fill(NAN);
}

void EnvelopeLayer::set_terrain(const TerrainHeightfield& t) {
  Impl& m = *impl_;
  m.ctx.wait_idle();  // a frame in flight may read the old one (a bake: rare)
  m.terrain = {};
  if (t.empty() || t.resolution == 0) return;
  if (std::abs(t.size.x - t.size.y) > 1e-3f * t.size.x)
    fail("envelope clouds: the terrain under the maps must be square (%.1f x %.1f m)", t.size.x, t.size.y);
  std::vector<float> heights(t.texels.size());
  // Sea level where no triangle covers a texel: the bake sets the envelope there on the sea (envelope_pass.cpp).
  for (size_t i = 0; i < heights.size(); ++i) heights[i] = std::max(t.texels[i].x, 0.0f);
  m.terrain = gpu::Image(m.ctx, gpu::ImageDesc::tex2d(t.resolution, t.resolution, VK_FORMAT_R32_SFLOAT,
                                                      VK_IMAGE_USAGE_SAMPLED_BIT, 1, "clouds.envelope.terrain"));
  m.terrain.upload({{heights.data(), heights.size() * sizeof(float)}});
  m.terrain_origin = t.origin;
  m.terrain_side = t.size.x;
  m.shadow_key.fill(NAN);
}

uint32_t EnvelopeLayer::shadow_updates() const { return impl_->shadow_marches; }

CloudFrameInputs::EnvelopeMedium EnvelopeLayer::add_medium(cumulo::render::RenderGraph& graph, const EnvelopeDraw& draw,
                                                           const EnvelopeMarchSettings& march, const CloudFrameInputs& in) {
  Impl& m = *impl_;
  if (draw.maps && draw.maps != m.maps) set_maps(draw.maps, in.frame_index + 1);
  if (!has_maps()) return {};
  const shared::EnvelopeParams p = m.params(draw, march, in, 0.0f, 1e9f);
  const gpu::Buffer& ubo = m.ubo[in.slot % gpu::kFramesInFlight][2];
  std::memcpy(ubo.mapped(), &p, sizeof p);
  return m.density_inputs(graph, ubo.handle());
}

namespace {

// A square map on the plane at `height` holding the corners `pts` carried along `l` onto it, one texel of margin (the
// border stays unshadowed).
cumulo::render::LightShadowMap square_map(const std::vector<glm::vec2>& pts, float height, uint32_t texels) {
  glm::vec2 lo(INFINITY), hi(-INFINITY);
  for (const glm::vec2& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const float side = std::max(std::max(hi.x - lo.x, hi.y - lo.y), 1.0f) * (1.0f + 2.0f / float(std::max(texels, 4u)));
  cumulo::render::LightShadowMap map;
  map.origin = 0.5f * (lo + hi) - glm::vec2(0.5f * side);
  map.size = glm::vec2(side);
  map.height = height;
  return map;
}

}  // namespace

cumulo::render::LightShadowMap EnvelopeLayer::add_shadow_passes(cumulo::render::RenderGraph& graph,
                                                                const EnvelopeDraw& draw,
                                                                const EnvelopeMarchSettings& march,
                                                                const CloudFrameInputs& in,
                                                                const cumulo::render::LightShadowMap& voxel) {
  Impl& m = *impl_;
  if (draw.maps && draw.maps != m.maps) set_maps(draw.maps, in.frame_index + 1);
  const glm::vec3 l = glm::normalize(in.sun_direction);
  if (!has_maps() || !m.terrain || !in.settings.shadows || l.y < kShadowMinLightHeight || !(m.box_lo.x <= m.box_hi.x))
    return voxel;
  if (!m.shadow_pipe) {
    m.shadow_pipe = &m.library.compute({.shader = "clouds/envelope_shadow.comp", .name = "clouds.envelope_shadow"});
    m.combine_pipe = &m.library.compute({.shader = "clouds/envelope_shadow_combine.comp", .name = "clouds.envelope_shadow_combine"});
    for (uint32_t i = 0; i < gpu::kFramesInFlight; ++i)
      m.shadow_ubo[i] = gpu::Buffer(m.ctx, {sizeof(shared::EnvelopeParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                            gpu::MemoryUsage::Dynamic, "clouds.envelope.shadow_params"});
  }
  auto ensure = [&](gpu::Image& img, cumulo::render::PersistentTexture& tex, uint32_t texels, const char* name) {
    texels = std::clamp(texels, 16u, 4096u);
    if (img && img.extent().width == texels) return;
    if (img) m.ctx.wait_idle();
    img = gpu::Image(m.ctx, gpu::ImageDesc::tex2d(texels, texels, VK_FORMAT_R16_SFLOAT,
                                                  VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT, 1, name));
    tex = {name, TextureDesc::absolute(VK_FORMAT_R16_SFLOAT, texels, texels), img.handle(), img.view(),
           cumulo::render::ResourceState::undefined()};
    if (&img == &m.env_shadow) m.shadow_key.fill(NAN);
    m.combined_key.fill(NAN);
  };
  ensure(m.env_shadow, m.env_shadow_tex, march.shadow_texels, "clouds.envelope.shadow");

  // The plane: under the envelope's lowest bottom and the voxel clouds' plane (a point between them reads both).
  const bool with_voxel = voxel.texture.valid();
  const float height = with_voxel ? std::min(m.box_lo.y, voxel.height) : m.box_lo.y;
  auto onto_plane = [&](glm::vec3 p) {
    const glm::vec3 q = p + l * ((height - p.y) / l.y);
    return glm::vec2(q.x, q.z);
  };
  std::vector<glm::vec2> corners;
  for (int c = 0; c < 8; ++c)
    corners.push_back(onto_plane(glm::vec3((c & 1) ? m.box_hi.x : m.box_lo.x, (c & 2) ? m.box_hi.y : m.box_lo.y,
                                           (c & 4) ? m.box_hi.z : m.box_lo.z)));
  const cumulo::render::LightShadowMap env_map = square_map(corners, height, m.env_shadow.extent().width);

  // The envelope's own map: marched when stale (every frame on a GPU).
  const shared::EnvelopeParams p = m.params(draw, march, in, 0.0f, 1e9f);
  const float texel_m = env_map.size.x / float(m.env_shadow.extent().width);
  const std::array<float, 11> key = {l.x, l.y, l.z, env_map.origin.x, env_map.origin.y, env_map.size.x, height,
                                  p.heights.w, p.noise.w, p.heights.z, p.wind.w};
  // The light and the plane exactly; the weather's density and coverage (7..10: they change every frame while the
  // weather turns) within 10 %, or a change of any size once it is kShadowWeatherFrames old. Before, a turning
  // weather re-marched the map every frame on a CPU device (`cumulo soak`: 115 ms a frame on lavapipe).
  constexpr uint64_t kShadowWeatherFrames = 8;
  bool geometry_same = true, weather_near = true, weather_same = true;
  for (size_t k = 0; k < key.size(); ++k) {
    if (k < 7) {
      geometry_same = geometry_same && key[k] == m.shadow_key[k];
    } else {
      weather_same = weather_same && key[k] == m.shadow_key[k];
      weather_near = weather_near && std::abs(key[k] - m.shadow_key[k]) <= 0.1f * std::max(std::abs(m.shadow_key[k]), 1e-3f);
    }
  }
  const bool weather_stale = !weather_same && (!weather_near || in.frame_index >= m.shadow_frame + kShadowWeatherFrames);
  const bool stale = march.shadow_every_frame || !geometry_same || weather_stale ||
                     glm::length(glm::vec3(p.wind) - m.shadow_scroll) > 0.5f * texel_m;
  TextureHandle env = graph.import_persistent(m.env_shadow_tex);
  if (stale) {
    const gpu::Buffer& ubo = m.shadow_ubo[in.slot % gpu::kFramesInFlight];
    std::memcpy(ubo.mapped(), &p, sizeof p);
    shared::EnvelopeShadowPush pc{};
    pc.plane = glm::vec4(env_map.origin, env_map.size);
    pc.light = glm::vec4(l, height);
    pc.terrain = glm::vec4(m.terrain_origin, m.terrain_side, std::max(std::min(m.maps->texel_m, texel_m), 1.0f));
    const CloudFrameInputs::EnvelopeMedium density = m.density_inputs(graph, ubo.handle());
    TextureHandle terrain = m.import(graph, "clouds.envelope.terrain", m.terrain);
    gpu::Pipeline* pipe = m.shadow_pipe;
    Impl* mp = &m;
    graph.add_pass("clouds.envelope_shadow", Queue::Compute,
        [&](PassBuilder& b) {
          Impl::read_density(b, density);
          b.read(terrain, Usage::Sampled);
          env = b.write(env, Usage::StorageWrite);
          b.side_effect();  // kept for the frames that reuse it
        },
        [mp, pipe, density, terrain, env, pc](PassContext& c) {
          pipe->bind(c.cmd());
          gpu::DescriptorWriter w;
          mp->bind_density(w, c, density)
              .sampled_image(ENV_BINDING_TERRAIN, c.view(terrain), mp->linear_clamp, c.layout(terrain))
              .storage_image(ENV_BINDING_SHADOW_OUT, c.view(env))
              .push(mp->ctx, c.cmd(), *pipe);
          pipe->push_constants(c.cmd(), pc);
          const VkExtent3D e = c.extent(env);
          pipe->dispatch_threads(c.cmd(), e.width, e.height);
        });
    m.shadow_key = key;
    m.shadow_scroll = glm::vec3(p.wind);
    m.shadow_frame = in.frame_index;
    ++m.shadow_marches;
  }
  cumulo::render::LightShadowMap out = env_map;
  out.texture = env;
  if (!with_voxel) return out;

  // With the voxel clouds' map: one map over both footprints on the lower plane.
  ensure(m.combined_shadow, m.combined_shadow_tex, march.combined_shadow_texels, "clouds.envelope.shadow_combined");
  const glm::vec2 shift = glm::vec2(l.x, l.z) * ((height - voxel.height) / l.y);  // a voxel-plane point onto this plane
  const std::vector<glm::vec2> both = {env_map.origin, env_map.origin + env_map.size, voxel.origin + shift,
                                       voxel.origin + voxel.size + shift};
  cumulo::render::LightShadowMap combined = square_map(both, height, m.combined_shadow.extent().width);
  shared::EnvelopeShadowCombinePush pc{};
  pc.plane = glm::vec4(combined.origin, combined.size);
  pc.light = glm::vec4(l, height);
  pc.envelope = glm::vec4(env_map.origin, env_map.size);
  pc.voxel_plane = glm::vec4(voxel.origin, voxel.size);
  pc.voxel = glm::vec4(voxel.height, 1.0f, 0.0f, 0.0f);
  TextureHandle dst = graph.import_persistent(m.combined_shadow_tex);
  combined.texture = dst;  // this frame's write (below) replaces the handle
  // Made again only when an input changed: the envelope's map, the voxel clouds' (its version), either plane.
  const std::array<float, 13> ckey = {float(m.shadow_marches), float(voxel.version), voxel.origin.x, voxel.origin.y,
                                   voxel.size.x, voxel.height, combined.origin.x, combined.origin.y, combined.size.x,
                                   height, l.x, l.y, l.z};
  if (voxel.version != 0 && ckey == m.combined_key) return combined;
  m.combined_key = ckey;
  const TextureHandle vox = voxel.texture;
  gpu::Pipeline* pipe = m.combine_pipe;
  Impl* mp = &m;
  graph.add_pass("clouds.envelope_shadow_combine", Queue::Compute,
      [&](PassBuilder& b) {
        b.read(env, Usage::Sampled);
        b.read(vox, Usage::Sampled);
        dst = b.write(dst, Usage::StorageWrite);
        b.side_effect();  // kept for the frames that reuse it
      },
      [mp, pipe, env, vox, dst, pc](PassContext& c) {
        pipe->bind(c.cmd());
        gpu::DescriptorWriter()
            .sampled_image(ENV_BINDING_SHADOW_IN, c.view(env), mp->linear_clamp, c.layout(env))
            .sampled_image(ENV_BINDING_VOXEL_SHADOW, c.view(vox), mp->linear_clamp, c.layout(vox))
            .storage_image(ENV_BINDING_SHADOW_OUT, c.view(dst))
            .push(mp->ctx, c.cmd(), *pipe);
        pipe->push_constants(c.cmd(), pc);
        const VkExtent3D e = c.extent(dst);
        pipe->dispatch_threads(c.cmd(), e.width, e.height);
      });
  combined.texture = dst;
  return combined;
}

bool envelope_in_view(const glm::mat4& view_proj, glm::vec3 lo, glm::vec3 hi) {
  if (!(lo.x <= hi.x)) return false;  // no envelope at all
  // Clip-space outcodes of the 8 corners: off screen when all lie beyond one plane (left, right, bottom, top, near).
  int all = 0x1f;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    const glm::vec4 c = view_proj * glm::vec4(p, 1.0f);
    int code = 0;
    if (c.x < -c.w) code |= 1;
    if (c.x > c.w) code |= 2;
    if (c.y < -c.w) code |= 4;
    if (c.y > c.w) code |= 8;
    if (c.w <= 0.0f) code |= 16;
    all &= code;
  }
  return all == 0;
}

uint64_t EnvelopeLayer::gpu_bytes() const {
  const Impl& m = *impl_;
  auto bytes = [](const gpu::Image& i, uint64_t texel) {
    return i ? uint64_t(i.extent().width) * i.extent().height * i.extent().depth * texel : 0ull;
  };
  return bytes(m.base, 4) + bytes(m.detail, 4) + bytes(m.shape, 16) + bytes(m.steps, 16) + bytes(m.aux, 16) +
         bytes(m.terrain, 4) + bytes(m.env_shadow, 2) + bytes(m.combined_shadow, 2);
}

std::vector<glm::vec4> EnvelopeLayer::probe(const EnvelopeDraw& draw, const EnvelopeMarchSettings& march,
                                            const CloudFrameInputs& in, const std::vector<glm::vec3>& points) {
  Impl& m = *impl_;
  if (points.empty()) return {};
  if (draw.maps && draw.maps != m.maps) set_maps(draw.maps, 0);
  if (!has_maps()) fail("envelope clouds: probe without baked maps");
  if (!m.probe) m.probe = &m.library.compute({.shader = "clouds/envelope_probe.comp", .name = "clouds.envelope_probe"});
  const shared::EnvelopeParams p = m.params(draw, march, in, 0.0f, 1e9f);
  gpu::Buffer ubo(m.ctx, {sizeof p, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic, "envelope probe params"});
  std::memcpy(ubo.mapped(), &p, sizeof p);
  const std::vector<uint8_t> bytes =
      run_point_probe(m.ctx, *m.probe, points, sizeof(glm::vec4), ENV_BINDING_PROBE_POINTS, ENV_BINDING_PROBE_OUT,
                      [&](gpu::DescriptorWriter& w) {
                        w.uniform_buffer(ENV_BINDING_PARAMS, ubo.handle(), 0, sizeof p)
                            .sampled_image(ENV_BINDING_SHAPE, m.shape.view(), m.linear_clamp)
                            .sampled_image(ENV_BINDING_STEPS, m.steps.view(), m.nearest_clamp)
                            .sampled_image(ENV_BINDING_AUX, m.aux.view(), m.linear_clamp)
                            .sampled_image(ENV_BINDING_BASE_NOISE, m.base.view(), m.linear_repeat)
                            .sampled_image(ENV_BINDING_DETAIL_NOISE, m.detail.view(), m.linear_repeat);
                      });
  std::vector<glm::vec4> out(points.size());
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

EnvelopeLayer::Outputs EnvelopeLayer::add_passes(cumulo::render::RenderGraph& graph, const EnvelopeDraw& draw,
                                                 const EnvelopeMarchSettings& march, const CloudFrameInputs& in,
                                                 TextureHandle scene_depth) {
  Impl& m = *impl_;
  if (draw.maps && draw.maps != m.maps) set_maps(draw.maps, in.frame_index + 1);
  if (!has_maps()) return {};
  if (!envelope_in_view(in.camera.view_proj, m.box_lo, m.box_hi)) {
    m.history.invalidate();  // what it held is of another view by the time the clouds come back
    m.near_history.invalidate();
    m.prev_view_proj = in.camera.view_proj;
    return {};
  }
  const float scale = std::clamp(march.resolution_scale, 0.125f, 1.0f) * in.resolution_scale;
  // The split's near pass only where the envelope comes within the split distance of the camera (as the voxel clouds
  // leave out theirs): from afar the far pass marches the whole ray.
  const bool split = march.split_m > 0.0f && envelope_within(*m.maps, in.camera.position, march.split_m);
  const TextureHandle terrain_depth = terrain_shadowed(in) ? in.terrain_depth : m.import(graph, "clouds.envelope.no_light_depth", m.no_light_depth);
  const TextureHandle voxel_shadow = in.voxel_shadow.texture.valid() ? in.voxel_shadow.texture : m.import(graph, "clouds.envelope.no_voxel_shadow", m.no_voxel_shadow);
  gpu::Pipeline* pipe = march.cone_stepping ? m.march_cone : m.march_fixed;
  Impl* mp = &m;

  // One segment of the rays [start, end) at `seg_scale` of the output, one pixel of each `block` x `block` a frame (at
  // `offset` in it) written at the block's texel.
  auto add_segment = [&](const char* pass, const char* color_name, const char* depth_name, uint32_t k, float seg_scale,
                         float start, float end, uint32_t block, glm::uvec2 offset) {
    const shared::EnvelopeParams p = m.params(draw, march, in, start, end);
    const gpu::Buffer& ubo = m.ubo[in.slot % gpu::kFramesInFlight][k];
    std::memcpy(ubo.mapped(), &p, sizeof p);
    const VkExtent2D full = cumulo::render::relative_extent(graph.output_size(), seg_scale);
    const uint32_t bw = (full.width + block - 1) / block, bh = (full.height + block - 1) / block;
    TextureHandle color = graph.create_texture(color_name, TextureDesc::absolute(VK_FORMAT_R16G16B16A16_SFLOAT, bw, bh));
    TextureHandle depth = graph.create_texture(depth_name, TextureDesc::absolute(VK_FORMAT_R32G32B32A32_SFLOAT, bw, bh));
    const CloudFrameInputs::EnvelopeMedium density = m.density_inputs(graph, ubo.handle());
    const uint32_t fw = full.width, fh = full.height;
    graph.add_pass(
        pass, Queue::Compute,
        [&](PassBuilder& b) {
          Impl::read_density(b, density);
          b.read(scene_depth, Usage::Sampled);
          b.read(terrain_depth, Usage::Sampled);
          b.read(voxel_shadow, Usage::Sampled);
          color = b.write(color, Usage::StorageWrite);
          depth = b.write(depth, Usage::StorageWrite);
        },
        [mp, pipe, density, scene_depth, terrain_depth, voxel_shadow, color, depth, fw, fh, block, offset](PassContext& c) {
          pipe->bind(c.cmd());
          gpu::DescriptorWriter w;
          mp->bind_density(w, c, density)
              .sampled_image(ENV_BINDING_SCENE_DEPTH, c.view(scene_depth), mp->nearest_clamp, c.layout(scene_depth))
              .storage_image(ENV_BINDING_OUT_COLOR, c.view(color))
              .storage_image(ENV_BINDING_OUT_DEPTH, c.view(depth))
              .sampled_image(ENV_BINDING_TERRAIN_DEPTH, c.view(terrain_depth), mp->nearest_clamp, c.layout(terrain_depth))
              .sampled_image(ENV_BINDING_VOXEL_SHADOW_MAP, c.view(voxel_shadow), mp->linear_clamp, c.layout(voxel_shadow))
              .push(mp->ctx, c.cmd(), *pipe);
          shared::CloudMarchPush pc{};
          pc.target = glm::vec4(float(fw), float(fh), 1.0f / float(fw), 1.0f / float(fh));
          pc.sub = glm::vec4(float(block), float(offset.x), float(offset.y), 0.0f);
          pipe->push_constants(c.cmd(), pc);
          const VkExtent3D e = c.extent(color);
          pipe->dispatch_threads(c.cmd(), e.width, e.height);
        });
    return std::make_pair(color, depth);
  };

  Outputs o;
  o.below_output_size = scale < 1.0f;
  // The reconstructions' camera block (both read P.steps.x, where the near pass ends).
  shared::CloudParams cp{};
  cp.inv_view_proj = in.camera.inv_view_proj;
  cp.view_proj = in.camera.view_proj;
  cp.prev_view_proj = m.prev_view_proj;
  cp.camera_pos = glm::vec4(in.camera.position, float(in.time));
  cp.steps = glm::vec4(split ? march.split_m : 1e9f, 0.0f, 0.0f, 0.0f);
  const gpu::Buffer& recon_ubo = m.recon_ubo[in.slot % gpu::kFramesInFlight];
  std::memcpy(recon_ubo.mapped(), &cp, sizeof cp);
  if (in.camera_cut) m.history.invalidate(), m.near_history.invalidate();
  const uint32_t near_block = std::clamp(march.near_block, 1u, 4u);
  if (split && near_block == 1) {
    const auto near = add_segment("clouds.envelope_near", "clouds.envelope.near_color", "clouds.envelope.near_depth", 0,
                                  0.5f * scale, 0.0f, march.split_m, 1, glm::uvec2(0));
    o.near_color = near.first, o.near_depth = near.second;
    m.near_history.invalidate();
  } else if (split) {
    // The near pass sub-sampled too (a CPU device; the voxel clouds' near segment marches 1 of 16 as well), its rays
    // ending at the split.
    m.near_history.set_scale(0.5f * scale);
    const cumulo::render::HistoryHandles hn = m.near_history.import(m.ctx, graph);
    const glm::uvec2 offset_n = reprojection_offset(near_block, in.frame_index);
    const auto sub_n = add_segment("clouds.envelope_near", "clouds.envelope.near_sub_color",
                                   "clouds.envelope.near_sub_depth", 0, 0.5f * scale, 0.0f, march.split_m, near_block,
                                   offset_n);
    TextureHandle next_n = hn.current;
    TextureHandle depth_n =
        graph.create_texture("clouds.envelope.near_depth", TextureDesc::relative(VK_FORMAT_R32G32B32A32_SFLOAT, 0.5f * scale));
    add_reconstruct_pass(graph, m.ctx, "clouds.envelope_reconstruct_near",
                         {m.reconstruct_near, recon_ubo.handle(), sub_n.first, sub_n.second, hn.previous, scene_depth,
                          near_block, offset_n, hn.valid},
                         next_n, depth_n);
    o.near_color = next_n, o.near_depth = depth_n;
  } else {
    m.near_history.invalidate();
  }
  const uint32_t block = std::clamp(march.far_block, 1u, 4u);
  const float far_start = split ? march.split_m : 0.0f;
  if (block == 1) {
    const auto far = add_segment(split ? "clouds.envelope_far" : "clouds.envelope", "clouds.envelope.color",
                                 "clouds.envelope.depth", 1, scale, far_start, 1e9f, 1, glm::uvec2(0));
    o.color = far.first, o.depth = far.second;
    m.history.invalidate();
    m.prev_view_proj = in.camera.view_proj;
    return o;
  }
  // Sub-sampled and reprojected (a CPU device): the far pass's history at the layer's scale; the split's near pass is
  // merged in by the reconstruction.
  m.history.set_scale(scale);
  const cumulo::render::HistoryHandles h = m.history.import(m.ctx, graph);
  const glm::uvec2 offset = reprojection_offset(block, in.frame_index);
  const auto sub = add_segment(split ? "clouds.envelope_far" : "clouds.envelope", "clouds.envelope.sub_color",
                               "clouds.envelope.sub_depth", 1, scale, far_start, 1e9f, block, offset);
  m.prev_view_proj = in.camera.view_proj;
  ReconstructInputs ri{split ? m.reconstruct_merge : m.reconstruct, recon_ubo.handle(), sub.first, sub.second,
                       h.previous, scene_depth, block, offset, h.valid};
  TextureHandle next = h.current;
  if (split) {
    ri.near_color = o.near_color, ri.near_depth = o.near_depth;
    TextureHandle unused_depth;
    ReconstructMerged merged{graph.create_texture("clouds.envelope.merged_color",
                                                  TextureDesc::relative(VK_FORMAT_R16G16B16A16_SFLOAT, scale)),
                             graph.create_texture("clouds.envelope.merged_depth",
                                                  TextureDesc::relative(VK_FORMAT_R32G32B32A32_SFLOAT, scale))};
    add_reconstruct_pass(graph, m.ctx, "clouds.envelope_reconstruct", ri, next, unused_depth, &merged);
    o.color = merged.color, o.depth = merged.depth;
    o.near_color = {}, o.near_depth = {};
  } else {
    TextureHandle out_d = graph.create_texture("clouds.envelope.depth", TextureDesc::relative(VK_FORMAT_R32G32B32A32_SFLOAT, scale));
    add_reconstruct_pass(graph, m.ctx, "clouds.envelope_reconstruct", ri, next, out_d);
    o.color = next, o.depth = out_d;
  }
  return o;
}

}  // namespace cumulo::clouds::render
