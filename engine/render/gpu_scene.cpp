#include "engine/render/gpu_scene.h"

#include <algorithm>

#include "engine/core/error.h"
#include "engine/gpu/context.h"
#include "engine/gpu/format.h"
#include "engine/gpu/sampler.h"

namespace cumulo::render {
namespace {

VkSamplerAddressMode address_mode(scene::Wrap w) {
  switch (w) {
    case scene::Wrap::ClampToEdge: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    case scene::Wrap::MirroredRepeat: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    case scene::Wrap::Repeat: break;
  }
  return VK_SAMPLER_ADDRESS_MODE_REPEAT;
}

// An RGBA8 texture with its box-filtered mip chain, uploaded (waits for the copy).
gpu::Image upload_texture(gpu::Context& ctx, const scene::Texture& t, VkFormat format, const std::string& name) {
  auto chain = build_mip_chain(t);
  gpu::Image img(ctx, gpu::ImageDesc::tex2d(t.width, t.height, format, VK_IMAGE_USAGE_SAMPLED_BIT, uint32_t(chain.size()),
                                            name.c_str()));
  std::vector<gpu::MipData> mips;
  for (auto& m : chain) mips.push_back({m.data(), m.size()});
  img.upload(mips);
  return img;
}

}  // namespace

std::vector<std::vector<uint8_t>> build_mip_chain(const scene::Texture& t) {
  std::vector<std::vector<uint8_t>> mips;
  mips.push_back(t.rgba);
  uint32_t w = t.width, h = t.height;
  while (w > 1 || h > 1) {
    uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
    const auto& src = mips.back();
    std::vector<uint8_t> dst(size_t(nw) * nh * 4);
    for (uint32_t y = 0; y < nh; ++y)
      for (uint32_t x = 0; x < nw; ++x)
        for (uint32_t c = 0; c < 4; ++c) {
          uint32_t sum = 0;
          for (uint32_t dy = 0; dy < 2; ++dy)
            for (uint32_t dx = 0; dx < 2; ++dx) {
              uint32_t sx = std::min(w - 1, x * 2 + dx), sy = std::min(h - 1, y * 2 + dy);
              sum += src[(size_t(sy) * w + sx) * 4 + c];
            }
          dst[(size_t(y) * nw + x) * 4 + c] = static_cast<uint8_t>((sum + 2) / 4);
        }
    mips.push_back(std::move(dst));
    w = nw;
    h = nh;
  }
  return mips;
}

GpuSceneCache::GpuSceneCache(gpu::Context& ctx) : ctx_(ctx) {
  white_ = gpu::Image(ctx, gpu::ImageDesc::tex2d(1, 1, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT, 1, "white"));
  const uint8_t px[4] = {255, 255, 255, 255};
  white_.upload({{px, 4}});
}

GpuSceneCache::~GpuSceneCache() = default;

const GpuModel& GpuSceneCache::get(const std::shared_ptr<const scene::Model>& model, float contour) {
  auto it = models_.find(model.get());
  if (it != models_.end()) return *it->second;

  auto g = std::make_unique<GpuModel>();
  g->source = model;
  std::string base = model->source.filename().string();
  for (size_t i = 0; i < model->textures.size(); ++i) {
    const scene::Texture& t = model->textures[i];
    if (t.width == 0 || t.height == 0 || t.rgba.size() != size_t(t.width) * t.height * 4)
      fail("%s: texture %zu (%s) has no valid RGBA8 pixels", model->source.string().c_str(), i, t.name.c_str());
    std::string name = base + ":" + (t.name.empty() ? "texture" + std::to_string(i) : t.name);
    g->textures.push_back(upload_texture(ctx_, t, t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM, name));
  }
  auto make_material = [&](const scene::Material* m) {
    GpuMaterial gm;
    gm.texture = white_.view();
    gm.sampler = ctx_.samplers().get(gpu::SamplerDesc::linear_repeat());
    if (!m) return gm;
    gm.base_color_factor = m->base_color_factor;
    gm.roughness = m->roughness;
    gm.metallic = m->metallic;
    gm.double_sided = m->double_sided;
    if (m->base_color_texture >= 0 && size_t(m->base_color_texture) < g->textures.size()) {
      const scene::Texture& t = model->textures[size_t(m->base_color_texture)];
      gpu::SamplerDesc sd;
      sd.filter = t.linear_filter ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
      sd.address = address_mode(t.wrap_u);  // one mode for u and v (the cache's description)
      gm.texture = g->textures[size_t(m->base_color_texture)].view();
      gm.textured = true;
      gm.sampler = ctx_.samplers().get(sd);
    }
    return gm;
  };
  for (const auto& m : model->materials) g->materials.push_back(make_material(&m));
  g->materials.push_back(make_material(nullptr));

  for (size_t i = 0; i < model->meshes.size(); ++i) {
    const scene::Mesh& m = model->meshes[i];
    GpuMesh gm;
    gm.material = m.material;
    gm.index_count = static_cast<uint32_t>(m.indices.size());
    if (m.vertices.empty() || m.indices.empty()) {
      g->meshes.push_back(std::move(gm));
      continue;
    }
    std::string vname = base + ":" + m.name + " vertices", iname = base + ":" + m.name + " indices";
    MeshLodSettings lod_settings;
    lod_settings.contour = contour;
    ChunkedMesh lods = build_mesh_lods(m, lod_settings);
    std::vector<scene::Vertex> vertices = m.vertices;  // then the skirts' (mesh_lod.h)
    vertices.insert(vertices.end(), lods.skirt_vertices.begin(), lods.skirt_vertices.end());
    gm.vertices = gpu::Buffer(ctx_, {vertices.size() * sizeof(scene::Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                     gpu::MemoryUsage::GpuOnly, vname.c_str()});
    gm.vertices.upload(vertices.data(), vertices.size() * sizeof(scene::Vertex));
    gm.index_count = static_cast<uint32_t>(lods.indices.size());
    gm.chunks = std::move(lods.chunks);
    if (lods.normals.width) {
      scene::Texture nt;
      nt.width = lods.normals.width;
      nt.height = lods.normals.height;
      nt.rgba = std::move(lods.normals.rgba);
      gm.normals = upload_texture(ctx_, nt, VK_FORMAT_R8G8B8A8_UNORM, base + ":" + m.name + " normals");
      gm.normal_plane_u = lods.normals.plane_u;
      gm.normal_plane_v = lods.normals.plane_v;
    }
    gm.indices = gpu::Buffer(ctx_, {lods.indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                    gpu::MemoryUsage::GpuOnly, iname.c_str()});
    gm.indices.upload(lods.indices.data(), lods.indices.size() * sizeof(uint32_t));
    g->meshes.push_back(std::move(gm));
  }
  auto& ref = *g;
  models_.emplace(model.get(), std::move(g));
  return ref;
}

}  // namespace cumulo::render
