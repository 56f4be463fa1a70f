#include "engine/render/height_field_normals.h"

#include <algorithm>
#include <cmath>

namespace cumulo::render {

HeightFieldNormals build_height_field_normals(const scene::Mesh& mesh, const std::vector<uint32_t>& tris, int u, int v,
                                              int h, uint32_t max_size) {
  HeightFieldNormals out;
  if (tris.size() < 3 || max_size < 2) return out;
  scene::Bounds box;
  for (uint32_t i : tris) box.add(mesh.vertices[i].position);
  const float su = box.max[u] - box.min[u], sv = box.max[v] - box.min[v];
  if (!(su > 0.0f) || !(sv > 0.0f)) return out;
  // The mean vertex spacing of a grid of this many triangles (two per cell) over the box.
  const float spacing = std::sqrt(su * sv / (float(tris.size() / 3) * 0.5f));
  auto texels = [&](float size) { return std::clamp(uint32_t(std::lround(2.0f * size / spacing)) + 1u, 2u, max_size); };
  const uint32_t w = texels(su), hgt = texels(sv);
  out.width = w;
  out.height = hgt;
  // Texel i's centre at box.min + i / (w - 1) of the size: texture coordinate (i + 0.5) / w.
  const float ku = float(w - 1) / float(w) / su, kv = float(hgt - 1) / float(hgt) / sv;
  out.plane_u[u] = ku;
  out.plane_u.w = 0.5f / float(w) - box.min[u] * ku;
  out.plane_v[v] = kv;
  out.plane_v.w = 0.5f / float(hgt) - box.min[v] * kv;

  std::vector<glm::vec3> normals(size_t(w) * hgt, glm::vec3(0.0f));
  std::vector<uint8_t> written(normals.size(), 0);
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    glm::vec2 q[3];
    glm::vec3 n[3];
    const glm::vec3 p0 = mesh.vertices[tris[t]].position, p1 = mesh.vertices[tris[t + 1]].position,
                    p2 = mesh.vertices[tris[t + 2]].position;
    glm::vec3 face = glm::cross(p1 - p0, p2 - p0);
    if (face[h] < 0.0f) face = -face;  // the normals face up the height axis
    for (int k = 0; k < 3; ++k) {
      const scene::Vertex& vx = mesh.vertices[tris[t + k]];
      q[k] = {(vx.position[u] - box.min[u]) / su * float(w - 1), (vx.position[v] - box.min[v]) / sv * float(hgt - 1)};
      const float len = glm::length(vx.normal);
      n[k] = len > 1e-6f && std::isfinite(len) ? vx.normal / len : glm::normalize(face);
    }
    const float det = (q[1].y - q[2].y) * (q[0].x - q[2].x) + (q[2].x - q[1].x) * (q[0].y - q[2].y);
    if (!(std::abs(det) > 1e-12f) || !std::isfinite(det)) continue;  // no area, or a corner not finite
    const int x0 = std::max(0, int(std::ceil(std::min({q[0].x, q[1].x, q[2].x}) - 1e-3f)));
    const int x1 = std::min(int(w) - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}) + 1e-3f)));
    const int y0 = std::max(0, int(std::ceil(std::min({q[0].y, q[1].y, q[2].y}) - 1e-3f)));
    const int y1 = std::min(int(hgt) - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}) + 1e-3f)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const float w0 = ((q[1].y - q[2].y) * (float(x) - q[2].x) + (q[2].x - q[1].x) * (float(y) - q[2].y)) / det;
        const float w1 = ((q[2].y - q[0].y) * (float(x) - q[2].x) + (q[0].x - q[2].x) * (float(y) - q[2].y)) / det;
        const float w2 = 1.0f - w0 - w1;
        constexpr float kEps = -1e-4f;
        if (w0 < kEps || w1 < kEps || w2 < kEps) continue;
        const size_t i = size_t(y) * w + size_t(x);
        normals[i] = w0 * n[0] + w1 * n[1] + w2 * n[2];
        written[i] = 1;
      }
  }
  // Texels under no triangle (a hole in the field) take a written neighbour's normal, ring by ring.
  for (bool holes = true; holes;) {
    holes = false;
    bool grew = false;
    std::vector<uint8_t> next = written;
    for (uint32_t y = 0; y < hgt; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        if (written[i]) continue;
        glm::vec3 sum(0.0f);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = int(x) + dx, ny = int(y) + dy;
            if (nx < 0 || ny < 0 || nx >= int(w) || ny >= int(hgt)) continue;
            const size_t j = size_t(ny) * w + size_t(nx);
            if (written[j]) sum += normals[j];
          }
        if (glm::length(sum) > 0.0f) {
          normals[i] = sum;
          next[i] = 1;
          grew = true;
        } else {
          holes = true;
        }
      }
    written.swap(next);
    if (!grew) break;  // nothing was written at all
  }
  out.rgba.resize(normals.size() * 4);
  glm::vec3 up(0.0f);
  up[h] = 1.0f;
  for (size_t i = 0; i < normals.size(); ++i) {
    const float len = glm::length(normals[i]);
    const glm::vec3 n = written[i] && len > 1e-6f ? normals[i] / len : up;
    for (int c = 0; c < 3; ++c) out.rgba[i * 4 + c] = uint8_t(std::lround(std::clamp(n[c] * 0.5f + 0.5f, 0.0f, 1.0f) * 255.0f));
    out.rgba[i * 4 + 3] = 255;
  }
  return out;
}

}  // namespace cumulo::render
