#include "engine/render/frame_renderer.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/context.h"
#include "engine/gpu/descriptors.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/gpu/sampler.h"
#include "engine/render/graph/executor.h"
#include "engine/render/gpu_scene.h"
#include "engine/render/light_depth.h"
#include "engine/render/pass_helpers.h"
#include "engine/render/uniform_allocator.h"
#include "engine/render/atmosphere/atmosphere_passes.h"
#include "engine/render/sky_model.h"
#include "engine/scene/camera.h"
#include "shaders/shared/frame_params.h"

namespace cumulo::render {
namespace {

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

bool is_srgb(VkFormat f) {
  return f == VK_FORMAT_R8G8B8A8_SRGB || f == VK_FORMAT_B8G8R8A8_SRGB || f == VK_FORMAT_A8B8G8R8_SRGB_PACK32;
}

}  // namespace

struct FrameRenderer::Impl {
  gpu::Context& ctx;
  gpu::PipelineLibrary library;  // hot reload swaps pipelines in place: the pointers stay valid
  Executor executor;
  GpuSceneCache scene;
  UniformAllocator uniforms;
  // The geometry pass's variants (geometry_variant): on a CPU device both sides of a branch run, so what a
  // frame does not use (point lights, a shadow map, the fog when the froxels light the air, a height
  // field's normal map) is compiled out.
  std::array<gpu::Pipeline*, 64> geometry_variants{};
  gpu::Pipeline* sky = nullptr;
  gpu::Pipeline* tonemap = nullptr;  // for tonemap_format
  // mesh_lod.h: a chunk's level may stray this many pixels at most (a silhouette, or the coastline, moves
  // that far when the level changes; the shading does not: a height field shades from its normal texture).
  // 3: the sample level's views at 640x360 stay within 38 dB of full detail, and mixed's geometry pass costs
  // a third of what it did at 0.25 px with the chunks' borders locked (13.9 -> 4.2 ms, 320x180, lavapipe).
  float lod_error_px = kDefaultLodErrorPx;
  // draw_models' scratch: the meshes in view and their chunks' draws
  struct MeshDraw {
    glm::mat4 world;
    const GpuMesh* mesh;
    const GpuMaterial* material;
  };
  struct QueuedDraw {
    ChunkDraw draw;
    uint32_t mesh;  // into meshes_drawn
  };
  std::vector<ChunkDraw> chunk_draws;
  std::vector<MeshDraw> meshes_drawn;
  std::vector<QueuedDraw> queued;
  std::unique_ptr<AtmospherePasses> atmosphere;  // its LUTs (the sky pass reads the sky view)
  gpu::Image no_shadow;  // 1x1 white: the geometry's light-shadow binding when no feature casts shadows
  std::unique_ptr<LightDepthMap> light_depth;  // the geometry from the key light (modules read it)
  VkFormat tonemap_format = VK_FORMAT_UNDEFINED;

  Impl(gpu::Context& c, const std::filesystem::path& shader_root)
      : ctx(c), library(c, shader_root), executor(c), scene(c), uniforms(c, kFramesInFlight) {
    if (!c.info().push_descriptors)
      fail("%s: the engine's passes need VK_KHR_push_descriptor, which this device lacks", c.info().name.c_str());
    build_scene_pipelines();
  }

  enum GeometryVariant : uint32_t { kDoubleSided = 1, kPointLights = 2, kShadowMap = 4, kAerialLut = 8, kNormalMap = 16,
                                    kBaseTexture = 32 };
  gpu::GraphicsPipelineDesc geometry_desc(uint32_t variant) const {
    const bool double_sided = variant & kDoubleSided;
    gpu::GraphicsPipelineDesc d;
    d.vertex = "engine/geometry_lit.vert";
    d.fragment = "engine/geometry_lit.frag";
    d.defines = {{"GEOMETRY_POINT_LIGHTS", variant & kPointLights ? "1" : "0"},
                 {"GEOMETRY_SHADOW_MAP", variant & kShadowMap ? "1" : "0"},
                 {"GEOMETRY_AERIAL_LUT", variant & kAerialLut ? "1" : "0"},
                 {"GEOMETRY_NORMAL_MAP", variant & kNormalMap ? "1" : "0"},
                 {"GEOMETRY_BASE_TEXTURE", variant & kBaseTexture ? "1" : "0"}};
    d.color_formats = {kHdrFormat};
    d.depth_format = kDepthFormat;
    d.depth_test = d.depth_write = true;
    d.depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed-Z (scene/camera.h)
    d.cull = double_sided ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
    d.front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;  // glTF; the projection's Y flip keeps CCW in framebuffer space
    d.vertex_bindings = {{0, sizeof(scene::Vertex), VK_VERTEX_INPUT_RATE_VERTEX}};
    d.vertex_attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(scene::Vertex, position)},
                           {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(scene::Vertex, normal)},
                           {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(scene::Vertex, uv)}};
    d.name = double_sided ? "geometry (double-sided)" : "geometry";
    return d;
  }
  gpu::Pipeline* geometry_variant(uint32_t variant) {
    gpu::Pipeline*& p = geometry_variants[variant];
    if (!p) p = &library.graphics(geometry_desc(variant));  // compiled on first use (prepare_geometry)
    return p;
  }
  static uint32_t frame_variant(const FrameSnapshot& s, bool shadow_map, bool aerial_lut) {
    return (s.lighting.point_lights.empty() ? 0u : kPointLights) | (shadow_map ? kShadowMap : 0u) |
           (aerial_lut ? kAerialLut : 0u);
  }
  static uint32_t mesh_variant(const GpuMesh& mesh, const GpuMaterial& material) {
    return (material.double_sided ? kDoubleSided : 0u) | (mesh.normals ? kNormalMap : 0u) |
           (material.textured ? kBaseTexture : 0u);
  }
  // Compiles the variants this frame's draws need before the graph records (a compile error then fails the
  // frame before any pass began, not inside the geometry pass).
  void prepare_geometry(const FrameSnapshot& s, uint32_t frame) {
    for (const ModelDraw& draw : s.models) {
      const GpuModel& gm = scene.get(draw.model);
      for (const scene::MeshInstance& inst : draw.model->instances) {
        const uint32_t v = frame | mesh_variant(gm.meshes[inst.mesh], gm.material(draw.model->meshes[inst.mesh].material));
        geometry_variant(v);
        // Its twin with (or without) a lightning flash's point lights too: the first flash of the night (no shadow
        // map) compiled one mid-game, a hitch `cumulo soak` saw as a pipeline made in its seventh lap.
        geometry_variant(v ^ kPointLights);
      }
    }
  }
  gpu::GraphicsPipelineDesc sky_desc() const {
    gpu::GraphicsPipelineDesc d;
    d.vertex = "engine/fullscreen.vert";
    d.fragment = "engine/sky_atmosphere.frag";
    d.color_formats = {kHdrFormat};
    d.depth_format = kDepthFormat;
    d.depth_test = true;
    d.depth_write = false;
    d.depth_compare = VK_COMPARE_OP_EQUAL;  // only where the cleared far plane (0) is left
    d.name = "sky";
    return d;
  }
  gpu::GraphicsPipelineDesc tonemap_desc(VkFormat out) const {
    gpu::GraphicsPipelineDesc d;
    d.vertex = "engine/fullscreen.vert";
    d.fragment = "engine/tonemap.frag";
    d.color_formats = {out};
    d.name = "tonemap";
    return d;
  }

  void build_scene_pipelines() {
    // The variants a level's frames use (an untextured mesh, a textured one, a height field; with and without
    // a lightning flash's point lights), compiled up front: a shader broken in any of their #if blocks fails
    // here, by name and line, not at the first flash. Others (the fog, no shadow map) compile at first use.
    for (uint32_t lights : {0u, uint32_t(kPointLights)})
      for (uint32_t v : {kShadowMap | kAerialLut, kShadowMap | kAerialLut | kBaseTexture | kNormalMap,
                         kDoubleSided | kShadowMap | kAerialLut | kBaseTexture})
        geometry_variant(v | lights);
    sky = &library.graphics(sky_desc());
    atmosphere = std::make_unique<AtmospherePasses>(ctx, library, default_atmosphere());
    const uint16_t one = 0x3C00;  // 1.0 in half precision
    no_shadow = gpu::Image::single_texel(ctx, VK_FORMAT_R16_SFLOAT, &one, sizeof one, "no light shadow");
    // 4 m texels over the 4 km sample level at 1024 (8 m at 512 on CPU devices, where the map's rare
    // re-renders cost more).
    light_depth = std::make_unique<LightDepthMap>(ctx, library, scene, ctx.info().is_cpu() ? 512u : 1024u);
  }
  void ensure_tonemap(VkFormat out) {
    if (tonemap && tonemap_format == out) return;
    tonemap = &library.graphics(tonemap_desc(out));  // one pipeline per output format, kept by the library
    tonemap_format = out;
  }

  // Every mesh's chunks, culled and at their level of detail, drawn front to back: the depth test then
  // rejects what lies behind before it is shaded (the terrain under the sea, a hill's far side), which on a
  // CPU device is most of the pass's cost.
  void draw_models(VkCommandBuffer cmd, const FrameSnapshot& s, const UniformSlice& ubo, VkImageView shadow,
                   VkImageLayout shadow_layout, VkImageView aerial, VkImageLayout aerial_layout, uint32_t frame) {
    // Linear, mipmapped, clamped: the shadow map, the froxels, the normals.
    const VkSampler shadow_sampler = ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
    scene::Frustum frustum = scene::Frustum::from(s.camera.view_proj);
    const float pixels_per_unit = std::abs(s.camera.proj[1][1]) * 0.5f * float(s.height);
    meshes_drawn.clear();
    queued.clear();
    for (const ModelDraw& draw : s.models) {
      const GpuModel& gm = scene.get(draw.model);
      for (const scene::MeshInstance& inst : draw.model->instances) {
        const scene::Mesh& mesh = draw.model->meshes[inst.mesh];
        const GpuMesh& gpu_mesh = gm.meshes[inst.mesh];
        if (!gpu_mesh.index_count || !gpu_mesh.vertices) continue;
        const glm::mat4 world = draw.world * inst.world;
        if (!frustum.intersects(mesh.bounds.transformed(world))) continue;
        const GpuMaterial& mat = gm.material(mesh.material);
        chunk_draws.clear();
        select_chunk_draws(gpu_mesh.chunks, world, frustum, s.camera.position, pixels_per_unit, lod_error_px, chunk_draws);
        for (const ChunkDraw& d : chunk_draws) queued.push_back({d, uint32_t(meshes_drawn.size())});
        meshes_drawn.push_back({world, &gpu_mesh, &mat});
      }
    }
    std::stable_sort(queued.begin(), queued.end(),
                     [](const QueuedDraw& a, const QueuedDraw& b) { return a.draw.distance < b.draw.distance; });
    const gpu::Pipeline* bound = nullptr;
    uint32_t current = UINT32_MAX;
    for (const QueuedDraw& q : queued) {
      if (q.mesh != current) {
        current = q.mesh;
        const MeshDraw& md = meshes_drawn[q.mesh];
        const bool normal_map = bool(md.mesh->normals);
        const gpu::Pipeline* p = geometry_variant(frame | mesh_variant(*md.mesh, *md.material));
        if (p != bound) {
          p->bind(cmd);
          bound = p;
        }
        gpu::DescriptorWriter()
            .uniform_buffer(FRAME_PARAMS_BINDING, ubo.buffer, ubo.offset, ubo.size)
            .sampled_image(GEOMETRY_BASE_COLOR_BINDING, md.material->texture, md.material->sampler)
            .sampled_image(GEOMETRY_LIGHT_SHADOW_BINDING, shadow, shadow_sampler, shadow_layout)
            .sampled_image(GEOMETRY_AERIAL_BINDING, aerial, shadow_sampler, aerial_layout)
            .sampled_image(GEOMETRY_NORMAL_BINDING, normal_map ? md.mesh->normals.view() : no_shadow.view(), shadow_sampler)
            .push(ctx, cmd, *p);
        shared::DrawParams dp{};
        dp.model = md.world;
        dp.normal_plane_u = md.mesh->normal_plane_u;
        dp.normal_plane_v = md.mesh->normal_plane_v;
        dp.base_color_factor = md.material->base_color_factor;
        dp.roughness = md.material->roughness;
        dp.metallic = md.material->metallic;
        dp.double_sided = md.material->double_sided ? 1u : 0u;
        p->push_constants(cmd, dp);
        VkDeviceSize offset = 0;
        VkBuffer vb = md.mesh->vertices.handle();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, md.mesh->indices.handle(), 0, VK_INDEX_TYPE_UINT32);
      }
      vkCmdDrawIndexed(cmd, q.draw.index_count, 1, q.draw.first_index, 0, 0);
    }
  }
};

FrameRenderer::FrameRenderer(gpu::Context& ctx, const std::filesystem::path& shader_root)
    : impl_(std::make_unique<Impl>(ctx, shader_root)) {}

FrameRenderer::~FrameRenderer() {
  if (features_.empty()) return;
  impl_->ctx.wait_idle();  // features free their objects now: no frame may still use them
  for (RenderFeature* f : features_) f->destroy_gpu();
}

void FrameRenderer::add_feature(RenderFeature& feature) {
  GpuServices services{impl_->ctx, impl_->library};
  try {
    feature.create_gpu(services);
  } catch (...) {
    // A failed create (a shader that does not compile) may have made some of the feature's objects: free
    // them now, while the device lives (the feature itself outlives the renderer and the device).
    impl_->ctx.wait_idle();
    feature.destroy_gpu();
    throw;
  }
  features_.push_back(&feature);
}

gpu::PipelineLibrary& FrameRenderer::pipeline_library() { return impl_->library; }

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::BeforeScene: return "before-scene";
    case Stage::AfterOpaque: return "after-opaque";
    case Stage::AfterTonemap: return "after-tonemap";
  }
  return "?";
}

const CompiledGraph& FrameRenderer::last_compiled() const { return impl_->executor.compiled(); }
bool FrameRenderer::has_recorded() const { return impl_->executor.has_executed(); }
FrameRenderer::GraphCache FrameRenderer::graph_cache() const {
  const Executor& e = impl_->executor;
  return {e.shape_count(), e.compile_count(), uint64_t(e.transient_bytes()), e.transient_image_count(), e.shapes_seen(),
          e.layout_count(), e.layouts_created()};
}

std::vector<std::pair<std::string, double>> FrameRenderer::pass_timings() const {
  std::vector<std::pair<std::string, double>> out;
  for (auto& t : impl_->executor.timings()) out.emplace_back(t.name, t.ms);
  return out;
}

std::pair<uint64_t, std::vector<std::pair<std::string, double>>> FrameRenderer::latest_completed_pass_timings() const {
  render::Executor::CompletedTimings t = impl_->executor.latest_completed_timings();
  std::vector<std::pair<std::string, double>> out;
  for (auto& p : t.passes) out.emplace_back(p.name, p.ms);
  return {t.frame, std::move(out)};
}

void FrameRenderer::record_frame(VkCommandBuffer cmd, const FrameSnapshot& s, const RenderTarget& target, uint32_t slot) {
  Impl& m = *impl_;
  m.ensure_tonemap(target.format);
  // Upload models before recording (uploads wait on the queue; they must not happen inside a pass).
  // The sea's level, where an opaque ocean draws a terrain's coastline, taken as in the model's own space (a
  // terrain placed level with the world): its levels of detail keep that line where it is.
  for (const ModelDraw& d : s.models) m.scene.get(d.model, s.ocean ? s.ocean->sea_level - d.world[3][1] : NAN);

  m.uniforms.begin_frame(slot);
  shared::FrameParams params = make_frame_params(s, exposure_ * s.lighting.exposure);
  params.aerial = glm::vec4(aerial_lut_ ? 1.0f : 0.0f, 0.0f, 0.0f, 0.0f);
  UniformSlice ubo = m.uniforms.push(params);

  RenderGraph graph(target.extent);
  TextureDesc out_desc = TextureDesc::absolute(target.format, target.extent.width, target.extent.height);
  TextureHandle out = graph.import_texture(target.name, out_desc, target.image, target.view, target.initial, target.final);
  StageContext frame{graph, s, m.ctx, m.library, m.uniforms, ubo, slot};
  frame.output_format = target.format;
  frame.hdr = graph.create_texture("hdr", TextureDesc::relative(kHdrFormat));
  frame.depth = graph.create_texture("depth", TextureDesc::relative(kDepthFormat));
  auto run_stage = [&](Stage stage) {
    for (RenderFeature* f : features_) f->add_passes(stage, frame);
  };
  if (!features_.empty()) frame.light_depth = m.light_depth->add_pass(graph, s);
  run_stage(Stage::BeforeScene);
  // A feature's light-shadow map (cloud shadows) reaches the scene passes through the frame parameters:
  // pushed again with the map's plane, for the geometry and every later stage.
  const LightShadowMap* published = frame.resources.find<LightShadowMap>();
  const LightShadowMap shadow = published ? *published : LightShadowMap{};
  if (shadow.texture.valid()) {
    shared::FrameParams with_shadow = params;
    with_shadow.shadow_plane = glm::vec4(shadow.origin, 1.0f / glm::max(shadow.size, glm::vec2(1e-3f)));
    with_shadow.shadow_misc = glm::vec4(shadow.height, 1.0f, 0.0f, 0.0f);
    ubo = frame.frame_params = m.uniforms.push(with_shadow);
  }

  // The geometry's shader variant for this frame (frame_variant), its pipelines compiled before recording.
  const uint32_t geometry_frame = Impl::frame_variant(s, shadow.texture.valid(), aerial_lut_);
  m.prepare_geometry(s, geometry_frame);
  // The atmosphere's LUTs (the sky view for the sky pass, the aerial perspective for the geometry).
  const AtmosphereLuts luts = m.atmosphere->add_passes(graph, s, slot);
  if (aerial_lut_) frame.resources.publish(AerialPerspective{luts.aerial});
  graph.add_pass("geometry", Queue::Graphics,
      [&](PassBuilder& b) {
        frame.hdr = b.write(frame.hdr, Usage::ColorAttachment);
        frame.depth = b.write(frame.depth, Usage::DepthWrite);
        if (shadow.texture.valid()) b.read(shadow.texture, Usage::Sampled);
        b.read(luts.aerial, Usage::Sampled);
      },
      [&m, &s, ubo, shadow, luts, geometry_frame, hdr = frame.hdr, depth = frame.depth](PassContext& c) {
        Attachment d{depth, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE};
        d.clear.depthStencil = {0.0f, 0};  // reversed-Z far plane
        begin_rendering(c, {hdr, VK_ATTACHMENT_LOAD_OP_CLEAR}, &d);
        const VkImageView aerial = c.view(luts.aerial);
        const VkImageLayout aerial_layout = c.layout(luts.aerial);
        if (shadow.texture.valid())
          m.draw_models(c.cmd(), s, ubo, c.view(shadow.texture), c.layout(shadow.texture), aerial, aerial_layout, geometry_frame);
        else
          m.draw_models(c.cmd(), s, ubo, m.no_shadow.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, aerial, aerial_layout, geometry_frame);
        vkCmdEndRendering(c.cmd());
      });

  graph.add_pass("sky", Queue::Graphics,
      [&](PassBuilder& b) {
        frame.hdr = b.read_write(frame.hdr, Usage::ColorAttachment);
        b.read(frame.depth, Usage::DepthRead);
        b.read(luts.sky_view, Usage::Sampled);
        b.read(luts.transmittance, Usage::Sampled);
      },
      [&m, ubo, luts, hdr = frame.hdr, depth = frame.depth](PassContext& c) {
        Attachment d{depth, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_NONE};
        begin_rendering(c, {hdr, VK_ATTACHMENT_LOAD_OP_LOAD}, &d);
        m.sky->bind(c.cmd());
        const VkSampler linear = m.ctx.samplers().get(gpu::SamplerDesc::linear_clamp());
        gpu::DescriptorWriter()
            .uniform_buffer(FRAME_PARAMS_BINDING, ubo.buffer, ubo.offset, ubo.size)
            .uniform_buffer(SKY_ATMOSPHERE_PARAMS_BINDING, luts.ubo, 0, sizeof(shared::AtmosphereGpuParams))
            .sampled_image(SKY_VIEW_BINDING, c.view(luts.sky_view), linear, c.layout(luts.sky_view))
            .sampled_image(SKY_TRANSMITTANCE_BINDING, c.view(luts.transmittance), linear, c.layout(luts.transmittance))
            .push(m.ctx, c.cmd(), *m.sky);
        vkCmdDraw(c.cmd(), 3, 1, 0, 0);
        vkCmdEndRendering(c.cmd());
      });

  run_stage(Stage::AfterOpaque);

  const float exposure = exposure_ * s.lighting.exposure;  // the renderer's, times the scene's meter
  const bool srgb_target = is_srgb(target.format);
  graph.add_pass("tonemap", Queue::Graphics,
      [&](PassBuilder& b) {
        b.read(frame.hdr, Usage::Sampled);
        out = b.write(out, Usage::ColorAttachment);
      },
      [&m, hdr = frame.hdr, out, exposure, srgb_target](PassContext& c) {
        begin_rendering(c, {out, VK_ATTACHMENT_LOAD_OP_DONT_CARE});
        m.tonemap->bind(c.cmd());
        gpu::DescriptorWriter()
            .sampled_image(TONEMAP_HDR_BINDING, c.view(hdr), m.ctx.samplers().get(gpu::SamplerDesc::nearest_clamp()))
            .push(m.ctx, c.cmd(), *m.tonemap);
        shared::TonemapParams tp{};
        tp.exposure = exposure;
        tp.op = TONEMAP_ACES;
        tp.output_srgb = srgb_target ? 1u : 0u;
        m.tonemap->push_constants(c.cmd(), tp);
        vkCmdDraw(c.cmd(), 3, 1, 0, 0);
        vkCmdEndRendering(c.cmd());
      });

  frame.output = out;
  run_stage(Stage::AfterTonemap);

  m.executor.execute(graph, cmd);
}

void FrameRenderer::set_lod_error_px(float px) { impl_->lod_error_px = px; }

bool FrameRenderer::reload_shaders() { return impl_->library.poll_reload() > 0; }

std::string FrameRenderer::shader_errors() const { return impl_->library.last_error(); }

}  // namespace cumulo::render
