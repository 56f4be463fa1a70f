#include "engine/render/frame_renderer.h"

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

void set_viewport(VkCommandBuffer cmd, VkExtent3D e) {
  VkViewport vp{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
  VkRect2D sc{{0, 0}, {e.width, e.height}};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &sc);
}

struct Attachment {
  TextureHandle handle;
  VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_LOAD;
  VkAttachmentStoreOp store = VK_ATTACHMENT_STORE_OP_STORE;
  VkClearValue clear{};
};

// Begins dynamic rendering over the colour target's extent, in the layouts the render graph chose for
// this pass (c.layout), and sets the full viewport. End it with vkCmdEndRendering.
void begin_rendering(PassContext& c, const Attachment& color, const Attachment* depth = nullptr) {
  auto info = [&c](const Attachment& a) {
    VkRenderingAttachmentInfo r{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    r.imageView = c.view(a.handle);
    r.imageLayout = c.layout(a.handle);
    r.loadOp = a.load;
    r.storeOp = a.store;
    r.clearValue = a.clear;
    return r;
  };
  VkRenderingAttachmentInfo color_info = info(color);
  VkRenderingAttachmentInfo depth_info = depth ? info(*depth) : VkRenderingAttachmentInfo{};
  VkExtent3D e = c.extent(color.handle);
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {e.width, e.height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = 1;
  ri.pColorAttachments = &color_info;
  ri.pDepthAttachment = depth ? &depth_info : nullptr;
  vkCmdBeginRendering(c.cmd(), &ri);
  set_viewport(c.cmd(), e);
}

}  // namespace

struct FrameRenderer::Impl {
  gpu::Context& ctx;
  gpu::PipelineLibrary library;  // hot reload swaps pipelines in place: the pointers stay valid
  Executor executor;
  GpuSceneCache scene;
  gpu::Buffer frame_ubo[kFramesInFlight];
  gpu::Pipeline* geometry = nullptr;
  gpu::Pipeline* geometry_double_sided = nullptr;
  gpu::Pipeline* sky = nullptr;
  gpu::Pipeline* tonemap = nullptr;  // for tonemap_format
  VkFormat tonemap_format = VK_FORMAT_UNDEFINED;

  explicit Impl(gpu::Context& c) : ctx(c), library(c), executor(c), scene(c) {
    if (!c.info().push_descriptors)
      fail("%s: the engine's passes need VK_KHR_push_descriptor, which this device lacks", c.info().name.c_str());
    for (uint32_t i = 0; i < kFramesInFlight; ++i)
      frame_ubo[i] = gpu::Buffer(c, {sizeof(shared::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryUsage::Dynamic,
                                     i == 0 ? "frame params 0" : "frame params 1"});
    build_scene_pipelines();
  }

  gpu::GraphicsPipelineDesc geometry_desc(bool double_sided) const {
    gpu::GraphicsPipelineDesc d;
    d.vertex = "engine/geometry_lit.vert";
    d.fragment = "engine/geometry_lit.frag";
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
  gpu::GraphicsPipelineDesc sky_desc() const {
    gpu::GraphicsPipelineDesc d;
    d.vertex = "engine/fullscreen.vert";
    d.fragment = "engine/sky_gradient.frag";
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
    geometry = &library.graphics(geometry_desc(false));
    geometry_double_sided = &library.graphics(geometry_desc(true));
    sky = &library.graphics(sky_desc());
  }
  void ensure_tonemap(VkFormat out) {
    if (tonemap && tonemap_format == out) return;
    tonemap = &library.graphics(tonemap_desc(out));  // one pipeline per output format, kept by the library
    tonemap_format = out;
  }

  void draw_models(VkCommandBuffer cmd, const FrameSnapshot& s, const gpu::Buffer& ubo) {
    scene::Frustum frustum = scene::Frustum::from(s.camera.view_proj);
    const gpu::Pipeline* bound = nullptr;
    for (const ModelDraw& draw : s.models) {
      const GpuModel& gm = scene.get(draw.model);
      for (const scene::MeshInstance& inst : draw.model->instances) {
        const scene::Mesh& mesh = draw.model->meshes[inst.mesh];
        const GpuMesh& gpu_mesh = gm.meshes[inst.mesh];
        if (!gpu_mesh.index_count || !gpu_mesh.vertices) continue;
        glm::mat4 world = draw.world * inst.world;
        if (!frustum.intersects(mesh.bounds.transformed(world))) continue;
        const GpuMaterial& mat = gm.material(mesh.material);
        const gpu::Pipeline* p = mat.double_sided ? geometry_double_sided : geometry;
        if (p != bound) {
          p->bind(cmd);
          bound = p;
        }
        gpu::DescriptorWriter()
            .uniform_buffer(0, ubo.handle(), 0, sizeof(shared::FrameParams))
            .sampled_image(1, mat.texture, mat.sampler)
            .push(ctx, cmd, *p);
        shared::DrawParams dp{};
        dp.model = world;
        dp.base_color_factor = mat.base_color_factor;
        dp.material = glm::vec4(mat.roughness, mat.metallic, mat.double_sided ? 1.0f : 0.0f, 0.0f);
        p->push_constants(cmd, dp);
        VkDeviceSize offset = 0;
        VkBuffer vb = gpu_mesh.vertices.handle();
        vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
        vkCmdBindIndexBuffer(cmd, gpu_mesh.indices.handle(), 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, gpu_mesh.index_count, 1, 0, 0, 0);
      }
    }
  }
};

FrameRenderer::FrameRenderer(gpu::Context& ctx) : impl_(std::make_unique<Impl>(ctx)) {}
FrameRenderer::~FrameRenderer() = default;

const CompiledGraph& FrameRenderer::last_compiled() const { return impl_->executor.compiled(); }

std::vector<std::pair<std::string, double>> FrameRenderer::pass_timings() const {
  std::vector<std::pair<std::string, double>> out;
  for (auto& t : impl_->executor.timings()) out.emplace_back(t.name, t.ms);
  return out;
}

void FrameRenderer::record_frame(VkCommandBuffer cmd, const FrameSnapshot& s, const RenderTarget& target, uint32_t slot) {
  Impl& m = *impl_;
  m.ensure_tonemap(target.format);
  // Upload models before recording (uploads wait on the queue; they must not happen inside a pass).
  for (const ModelDraw& d : s.models) m.scene.get(d.model);

  const gpu::Buffer& ubo = m.frame_ubo[slot % kFramesInFlight];
  shared::FrameParams params = make_frame_params(s, exposure_);
  std::memcpy(ubo.mapped(), &params, sizeof params);

  RenderGraph graph(target.extent);
  TextureDesc out_desc = TextureDesc::absolute(target.format, target.extent.width, target.extent.height);
  TextureHandle out = graph.import_texture(target.name, out_desc, target.image, target.view, target.initial, target.final);
  FrameResources frame;
  frame.hdr = graph.create_texture("hdr", TextureDesc::relative(kHdrFormat));
  frame.depth = graph.create_texture("depth", TextureDesc::relative(kDepthFormat));

  graph.add_pass("geometry", Queue::Graphics,
      [&](PassBuilder& b) {
        frame.hdr = b.write(frame.hdr, Usage::ColorAttachment);
        frame.depth = b.write(frame.depth, Usage::DepthWrite);
      },
      [&m, &s, &ubo, hdr = frame.hdr, depth = frame.depth](PassContext& c) {
        Attachment d{depth, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE};
        d.clear.depthStencil = {0.0f, 0};  // reversed-Z far plane
        begin_rendering(c, {hdr, VK_ATTACHMENT_LOAD_OP_CLEAR}, &d);
        m.draw_models(c.cmd(), s, ubo);
        vkCmdEndRendering(c.cmd());
      });

  graph.add_pass("sky", Queue::Graphics,
      [&](PassBuilder& b) {
        frame.hdr = b.read_write(frame.hdr, Usage::ColorAttachment);
        b.read(frame.depth, Usage::DepthRead);
      },
      [&m, &ubo, hdr = frame.hdr, depth = frame.depth](PassContext& c) {
        Attachment d{depth, VK_ATTACHMENT_LOAD_OP_LOAD, VK_ATTACHMENT_STORE_OP_NONE};
        begin_rendering(c, {hdr, VK_ATTACHMENT_LOAD_OP_LOAD}, &d);
        m.sky->bind(c.cmd());
        gpu::DescriptorWriter().uniform_buffer(0, ubo.handle(), 0, sizeof(shared::FrameParams)).push(m.ctx, c.cmd(), *m.sky);
        vkCmdDraw(c.cmd(), 3, 1, 0, 0);
        vkCmdEndRendering(c.cmd());
      });

  for (auto& hook : hooks_) hook(graph, s, frame);

  const float exposure = exposure_;
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
            .sampled_image(0, c.view(hdr), m.ctx.samplers().get(gpu::SamplerDesc::nearest_clamp()))
            .push(m.ctx, c.cmd(), *m.tonemap);
        shared::TonemapParams tp{};
        tp.params = glm::vec4(exposure, 0.0f, srgb_target ? 1.0f : 0.0f, 0.0f);
        m.tonemap->push_constants(c.cmd(), tp);
        vkCmdDraw(c.cmd(), 3, 1, 0, 0);
        vkCmdEndRendering(c.cmd());
      });

  m.executor.execute(graph, cmd);
}

bool FrameRenderer::reload_shaders() { return impl_->library.poll_reload() > 0; }

std::string FrameRenderer::shader_errors() const { return impl_->library.last_error(); }

}  // namespace cumulo::render
