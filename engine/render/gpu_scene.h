#pragma once
// GPU copies of the CPU models a snapshot draws: one vertex + index buffer per mesh, one sampled image
// (with a CPU-built mip chain) per texture, material constants. Uploaded on first use, kept while the
// renderer lives; keyed by the immutable scene::Model the level loaded (shared_ptr keeps it alive).
#include <cmath>
#include <memory>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/mesh_lod.h"
#include "engine/gpu/buffer.h"
#include "engine/gpu/image.h"
#include "engine/scene/model.h"

namespace cumulo::gpu {
class Context;
}

namespace cumulo::render {

struct GpuMesh {
  gpu::Buffer vertices, indices;
  uint32_t index_count = 0;  // in `indices`: every chunk's every level (0: nothing to draw)
  std::vector<MeshChunk> chunks;  // index ranges per chunk and level (mesh_lod.h); one chunk for small meshes
  int material = -1;
  gpu::Image normals;  // a chunked height field's shading normals (height_field_normals.h); empty otherwise
  glm::vec4 normal_plane_u{0.0f}, normal_plane_v{0.0f};
};

struct GpuMaterial {
  glm::vec4 base_color_factor{1.0f};
  float roughness = 1.0f, metallic = 0.0f;
  bool double_sided = false;
  VkImageView texture = VK_NULL_HANDLE;  // never null: a white texture stands in
  bool textured = false;                 // false: `texture` is the white stand-in (the shader skips it)
  VkSampler sampler = VK_NULL_HANDLE;
};

struct GpuModel {
  std::shared_ptr<const scene::Model> source;
  std::vector<GpuMesh> meshes;
  std::vector<gpu::Image> textures;
  std::vector<GpuMaterial> materials;  // materials.back() is the default material
  const GpuMaterial& material(int index) const {
    return index >= 0 && size_t(index) + 1 < materials.size() ? materials[size_t(index)] : materials.back();
  }
};

class GpuSceneCache {
 public:
  explicit GpuSceneCache(gpu::Context& ctx);
  ~GpuSceneCache();
  // Uploads on first use (waits for the copies), then returns the cached copy. `contour`: the height in the
  // model's own space whose contour line shows on its meshes (the sea level; MeshLodSettings::contour), for
  // the levels of detail built at that first use.
  const GpuModel& get(const std::shared_ptr<const scene::Model>& model, float contour = NAN);
  size_t model_count() const { return models_.size(); }

 private:
  gpu::Context& ctx_;
  gpu::Image white_;
  std::unordered_map<const scene::Model*, std::unique_ptr<GpuModel>> models_;
};

// Box-filtered RGBA8 mip chain of a texture (mip 0 = the texture itself), for upload.
std::vector<std::vector<uint8_t>> build_mip_chain(const scene::Texture& texture);

}  // namespace cumulo::render
