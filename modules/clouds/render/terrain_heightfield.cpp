#include "modules/clouds/render/terrain_heightfield.h"

#include <algorithm>
#include <cmath>

#include "engine/scene/model.h"

namespace cumulo::clouds::render {
namespace {

float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// The base colour at a uv (nearest texel, the sampler's wrap), linear; the factor alone without a texture.
struct MaterialSampler {
  glm::vec3 factor{1.0f};
  const scene::Texture* texture = nullptr;
  glm::vec3 at(glm::vec2 uv) const {
    if (!texture || texture->width == 0 || texture->height == 0) return factor;
    auto wrap = [](float v, scene::Wrap w) {
      if (w == scene::Wrap::ClampToEdge) return std::clamp(v, 0.0f, 1.0f);
      if (w == scene::Wrap::MirroredRepeat) {
        const float f = std::fmod(std::fabs(v), 2.0f);
        return f > 1.0f ? 2.0f - f : f;
      }
      return v - std::floor(v);
    };
    const uint32_t x = std::min(texture->width - 1, uint32_t(wrap(uv.x, texture->wrap_u) * float(texture->width)));
    const uint32_t y = std::min(texture->height - 1, uint32_t(wrap(uv.y, texture->wrap_v) * float(texture->height)));
    const uint8_t* p = &texture->rgba[(size_t(y) * texture->width + x) * 4];
    glm::vec3 c;
    for (int k = 0; k < 3; ++k) c[k] = texture->srgb ? srgb_to_linear(float(p[k]) / 255.0f) : float(p[k]) / 255.0f;
    return factor * c;
  }
};
MaterialSampler material_sampler(const scene::Model& m, int material) {
  MaterialSampler s;
  if (material < 0 || material >= int(m.materials.size())) return s;
  const scene::Material& mat = m.materials[size_t(material)];
  s.factor = glm::vec3(mat.base_color_factor);
  if (mat.base_color_texture >= 0 && mat.base_color_texture < int(m.textures.size())) s.texture = &m.textures[size_t(mat.base_color_texture)];
  return s;
}

}  // namespace

TerrainHeightfield rasterize_heightfield(const std::vector<cumulo::render::ModelDraw>& models, uint32_t resolution) {
  scene::Bounds bounds;
  for (const cumulo::render::ModelDraw& d : models)
    if (d.model) bounds.add(d.model->bounds.transformed(d.world));
  if (bounds.empty()) return {};
  return rasterize_heightfield(models, resolution, glm::vec2(bounds.min.x, bounds.min.z),
                               std::max(bounds.size().x, bounds.size().z));
}

TerrainHeightfield rasterize_heightfield(const std::vector<cumulo::render::ModelDraw>& models, uint32_t resolution,
                                         glm::vec2 origin, float side) {
  TerrainHeightfield h;
  if (resolution == 0 || !(side > 0.0f) || !std::isfinite(side)) return h;
  h.resolution = resolution;
  h.origin = origin;
  h.size = glm::vec2(side);
  h.texels.assign(size_t(resolution) * resolution, glm::vec4(TerrainHeightfield::kNoTerrain, 0.0f, 0.0f, 0.0f));
  const float texel = side / float(resolution);
  for (const cumulo::render::ModelDraw& d : models) {
    if (!d.model) continue;
    const scene::Model& m = *d.model;
    for (const scene::MeshInstance& inst : m.instances) {
      const scene::Mesh& mesh = m.meshes[inst.mesh];
      const MaterialSampler material = material_sampler(m, mesh.material);
      const glm::mat4 world = d.world * inst.world;
      std::vector<glm::vec3> p(mesh.vertices.size());
      for (size_t i = 0; i < p.size(); ++i) p[i] = glm::vec3(world * glm::vec4(mesh.vertices[i].position, 1.0f));
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        if (i0 >= p.size() || i1 >= p.size() || i2 >= p.size()) continue;  // (the loader checks indices; never trust twice)
        const glm::vec3 v0 = p[i0], v1 = p[i1], v2 = p[i2];
        const glm::vec2 uv0 = mesh.vertices[i0].uv, uv1 = mesh.vertices[i1].uv, uv2 = mesh.vertices[i2].uv;
        // Texel coordinates of the corners; the texels whose centres lie inside the triangle's xz shadow.
        const glm::vec2 q0 = (glm::vec2(v0.x, v0.z) - h.origin) / texel, q1 = (glm::vec2(v1.x, v1.z) - h.origin) / texel,
                        q2 = (glm::vec2(v2.x, v2.z) - h.origin) / texel;
        const float area = (q1.x - q0.x) * (q2.y - q0.y) - (q2.x - q0.x) * (q1.y - q0.y);
        if (std::fabs(area) < 1e-9f) continue;  // vertical: its neighbours cover it from above
        const int x0 = std::max(0, int(std::floor(std::min({q0.x, q1.x, q2.x}) - 0.5f)));
        const int x1 = std::min(int(resolution) - 1, int(std::ceil(std::max({q0.x, q1.x, q2.x}) - 0.5f)));
        const int y0 = std::max(0, int(std::floor(std::min({q0.y, q1.y, q2.y}) - 0.5f)));
        const int y1 = std::min(int(resolution) - 1, int(std::ceil(std::max({q0.y, q1.y, q2.y}) - 0.5f)));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const glm::vec2 c(float(x) + 0.5f, float(y) + 0.5f);
            const float w0 = ((q1.x - c.x) * (q2.y - c.y) - (q2.x - c.x) * (q1.y - c.y)) / area;
            const float w1 = ((q2.x - c.x) * (q0.y - c.y) - (q0.x - c.x) * (q2.y - c.y)) / area;
            const float w2 = 1.0f - w0 - w1;
            if (w0 < -1e-5f || w1 < -1e-5f || w2 < -1e-5f) continue;
            const float y_world = w0 * v0.y + w1 * v1.y + w2 * v2.y;
            glm::vec4& dst = h.texels[size_t(y) * resolution + size_t(x)];
            if (y_world > dst.x) dst = glm::vec4(y_world, material.at(w0 * uv0 + w1 * uv1 + w2 * uv2));
          }
      }
    }
  }
  h.min_height = INFINITY, h.max_height = -INFINITY;
  for (const glm::vec4& t : h.texels)
    if (t.x > TerrainHeightfield::kNoTerrain) h.min_height = std::min(h.min_height, t.x), h.max_height = std::max(h.max_height, t.x);
  if (h.min_height > h.max_height) return TerrainHeightfield{};
  return h;
}

float TerrainHeightfield::height_at(float x, float z, float none) const {
  if (empty()) return none;
  const float texel = size.x / float(resolution);
  const float fx = (x - origin.x) / texel - 0.5f, fz = (z - origin.y) / texel - 0.5f;
  const int x0 = int(std::floor(fx)), z0 = int(std::floor(fz));
  const float ax = fx - float(x0), az = fz - float(z0);
  float sum = 0.0f, weight = 0.0f;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int xi = x0 + i, zj = z0 + j;
      if (xi < 0 || zj < 0 || xi >= int(resolution) || zj >= int(resolution)) continue;
      const float h = texels[size_t(zj) * resolution + size_t(xi)].x;
      if (h <= kNoTerrain) continue;
      const float w = (i ? ax : 1.0f - ax) * (j ? az : 1.0f - az);
      sum += w * h, weight += w;
    }
  return weight > 1e-6f ? sum / weight : none;
}

}  // namespace cumulo::clouds::render
