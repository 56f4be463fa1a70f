#include "engine/render/light_depth.h"

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/core/hash.h"
#include "engine/gpu/context.h"
#include "engine/gpu/pipeline.h"
#include "engine/gpu/pipeline_library.h"
#include "engine/render/gpu_scene.h"
#include "engine/render/pass_helpers.h"
#include "engine/render/sky_model.h"

namespace cumulo::render {

namespace {

struct LightDepthPush {
  glm::mat4 world_to_light;
  glm::mat4 model;
};

}  // namespace

LightDepthMap::LightDepthMap(gpu::Context& ctx, gpu::PipelineLibrary& library, GpuSceneCache& scene, uint32_t size)
    : ctx_(ctx), scene_(scene), size_(size) {
  gpu::GraphicsPipelineDesc d;
  d.vertex = "engine/light_depth.vert";
  d.fragment = "engine/light_depth.frag";
  d.depth_format = VK_FORMAT_D32_SFLOAT;
  d.depth_test = d.depth_write = true;
  d.depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL;  // 0 at the light's side
  d.cull = VK_CULL_MODE_NONE;                     // both faces hide the light
  d.vertex_bindings = {{0, sizeof(scene::Vertex), VK_VERTEX_INPUT_RATE_VERTEX}};
  d.vertex_attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(scene::Vertex, position)}};
  d.name = "light depth";
  pipe_ = &library.graphics(d);
  image_ = gpu::Image(ctx, gpu::ImageDesc::tex2d(size, size, VK_FORMAT_D32_SFLOAT,
                                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT, 1,
                                                 "light depth"));
  texture_ = {"light_depth", TextureDesc::absolute(VK_FORMAT_D32_SFLOAT, size, size), image_.handle(), image_.view(),
              ResourceState::undefined()};
}

LightDepthMap::~LightDepthMap() = default;

LightDepth LightDepthMap::add_pass(RenderGraph& graph, const FrameSnapshot& s) {
  const glm::vec3 l = glm::normalize(key_light_direction(s));
  scene::Bounds bounds;
  struct KeyPart {
    const void* model;
    float m[16];
  };
  uint64_t key = 0x51ed27u;
  for (const ModelDraw& d : s.models) {
    for (const scene::MeshInstance& inst : d.model->instances)
      bounds.add(d.model->meshes[inst.mesh].bounds.transformed(d.world * inst.world));
    KeyPart k{d.model.get(), {}};
    std::memcpy(k.m, &d.world[0][0], sizeof k.m);
    key = hash64(&k, sizeof k, key);
  }
  if (bounds.empty() || l.y < 0.02f) return {};
  const bool rebuild = !valid_ || key != key_ ||
                       glm::dot(l, light_) < std::cos(glm::radians(kLightDepthRebuildDegrees));
  TextureHandle tex = graph.import_persistent(texture_);
  if (!rebuild) {
    LightDepth out = last_;
    out.texture = tex;
    return out;
  }
  // An orthographic box along the light around the bounds' corners.
  const glm::vec3 c = bounds.center();
  const float r = 0.5f * glm::length(bounds.size()) + 1.0f;
  const glm::vec3 up = std::fabs(l.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  const glm::mat4 view = glm::lookAtRH(c + l * r, c, up);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 p((i & 1) ? bounds.max.x : bounds.min.x, (i & 2) ? bounds.max.y : bounds.min.y,
                      (i & 4) ? bounds.max.z : bounds.min.z);
    const glm::vec3 v = glm::vec3(view * glm::vec4(p, 1.0f));
    lo = glm::min(lo, v), hi = glm::max(hi, v);
  }
  // View space looks down -z: near = -hi.z, far = -lo.z.
  const glm::mat4 proj = glm::orthoRH_ZO(lo.x, hi.x, lo.y, hi.y, -hi.z - 1.0f, -lo.z + 1.0f);
  LightDepth out;
  out.world_to_light = proj * view;
  out.depth_range_m = (hi.z - lo.z) + 2.0f;
  const glm::mat4 vp = out.world_to_light;
  LightDepthMap* self = this;
  const FrameSnapshot* snap = &s;
  graph.add_pass("light_depth", Queue::Graphics,
      [&](PassBuilder& b) {
        tex = b.write(tex, Usage::DepthWrite);
        b.side_effect();  // kept for later frames even when no pass reads it this frame
      },
      [self, snap, vp, tex](PassContext& c) {
        Attachment d{tex, VK_ATTACHMENT_LOAD_OP_CLEAR, VK_ATTACHMENT_STORE_OP_STORE};
        d.clear.depthStencil = {1.0f, 0};
        begin_rendering(c, nullptr, &d);
        self->pipe_->bind(c.cmd());
        for (const ModelDraw& draw : snap->models) {
          const GpuModel& gm = self->scene_.get(draw.model);
          for (const scene::MeshInstance& inst : draw.model->instances) {
            const GpuMesh& mesh = gm.meshes[inst.mesh];
            if (!mesh.index_count || !mesh.vertices) continue;
            LightDepthPush pc{vp, draw.world * inst.world};
            self->pipe_->push_constants(c.cmd(), pc);
            VkDeviceSize offset = 0;
            VkBuffer vb = mesh.vertices.handle();
            vkCmdBindVertexBuffers(c.cmd(), 0, 1, &vb, &offset);
            vkCmdBindIndexBuffer(c.cmd(), mesh.indices.handle(), 0, VK_INDEX_TYPE_UINT32);
            for (const MeshChunk& chunk : mesh.chunks) {  // level 0: the map is re-made rarely, keep it exact
              const MeshLodLevel& full = chunk.levels[0];  // its surface: a skirt hangs where no light reaches
              vkCmdDrawIndexed(c.cmd(), full.index_count - full.skirt_count, 1, full.first_index, 0, 0);
            }
          }
        }
        vkCmdEndRendering(c.cmd());
      });
  key_ = key;
  light_ = l;
  valid_ = true;
  ++renders_;
  last_ = out;
  out.texture = tex;
  return out;
}

}  // namespace cumulo::render
