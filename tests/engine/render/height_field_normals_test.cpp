// engine/render/height_field_normals.h: a height field's normals as a texture over its plane. A texel at a
// vertex holds that vertex's normal, a texel inside a triangle the interpolated one; the texel centres at the
// box's edges (a neighbouring mesh samples the same border); holes take a neighbour's normal.
#include "engine/render/height_field_normals.h"

#include <gtest/gtest.h>

#include <cmath>

namespace cumulo::render {
namespace {

// n x n vertices `spacing` apart over x and z, each with the normal of the analytic surface y = f(x, z).
scene::Mesh bumpy_grid(int n, float spacing) {
  scene::Mesh m;
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      const float fx = float(x) * spacing, fz = float(z) * spacing;
      const float y = 20.0f * std::sin(fx * 0.02f) * std::cos(fz * 0.03f);
      const float dx = 20.0f * 0.02f * std::cos(fx * 0.02f) * std::cos(fz * 0.03f);
      const float dz = -20.0f * 0.03f * std::sin(fx * 0.02f) * std::sin(fz * 0.03f);
      m.vertices.push_back({{fx, y, fz}, glm::normalize(glm::vec3(-dx, 1.0f, -dz)), {0, 0}});
    }
  for (int z = 0; z + 1 < n; ++z)
    for (int x = 0; x + 1 < n; ++x) {
      const uint32_t a = uint32_t(z * n + x), b = a + 1, c = a + uint32_t(n), d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  return m;
}

glm::vec3 texel(const HeightFieldNormals& t, uint32_t x, uint32_t y) {
  const uint8_t* p = &t.rgba[(size_t(y) * t.width + x) * 4];
  return glm::vec3(p[0], p[1], p[2]) / 255.0f * 2.0f - 1.0f;
}

TEST(HeightFieldNormals, TexelsAtVerticesHoldTheirNormalsAndTheBoxEdgesAreTexelCentres) {
  const int n = 33;
  const scene::Mesh m = bumpy_grid(n, 8.0f);  // 256 x 256 m
  const HeightFieldNormals t = build_height_field_normals(m, m.indices, 0, 2, 1);
  ASSERT_EQ(t.width, 65u);  // two texels per vertex spacing, one more for the far edge
  ASSERT_EQ(t.height, 65u);
  ASSERT_EQ(t.rgba.size(), size_t(65) * 65 * 4);
  // The planes map the box's corners to the first and last texels' centres.
  auto uv = [&](glm::vec3 p) { return glm::vec2(glm::dot(glm::vec4(p, 1.0f), t.plane_u), glm::dot(glm::vec4(p, 1.0f), t.plane_v)); };
  EXPECT_NEAR(uv({0, 0, 0}).x, 0.5f / 65.0f, 1e-6f);
  EXPECT_NEAR(uv({256, 0, 256}).x, 1.0f - 0.5f / 65.0f, 1e-6f);
  EXPECT_NEAR(uv({256, 50, 0}).y, 0.5f / 65.0f, 1e-6f);  // the height does not move it
  EXPECT_NEAR(uv({0, 0, 256}).y, 1.0f - 0.5f / 65.0f, 1e-6f);
  // Every vertex's texel (every second one) holds its normal, to 8 bits.
  for (int z = 0; z < n; ++z)
    for (int x = 0; x < n; ++x) {
      const glm::vec3 want = m.vertices[size_t(z * n + x)].normal, got = texel(t, uint32_t(2 * x), uint32_t(2 * z));
      EXPECT_NEAR(glm::length(got - want), 0.0f, 0.012f) << x << ", " << z;
    }
  // Between vertices: the triangle's interpolated normal (the midpoint of the diagonal b-c of cell (3, 5)).
  const glm::vec3 mid = glm::normalize(m.vertices[size_t(5 * n + 4)].normal + m.vertices[size_t(6 * n + 3)].normal);
  EXPECT_NEAR(glm::length(texel(t, 7, 11) - mid), 0.0f, 0.012f);
}

TEST(HeightFieldNormals, AHoleTakesItsNeighboursNormalAndDegenerateInputGivesNoTexture) {
  const int n = 17;
  scene::Mesh m = bumpy_grid(n, 8.0f);
  // Every vertex tilted the same way, then one cell's two triangles taken out.
  for (scene::Vertex& v : m.vertices) v.normal = glm::normalize(glm::vec3(0.3f, 1.0f, 0.0f));
  std::vector<uint32_t> holed;
  for (size_t i = 0; i < m.indices.size(); i += 6)
    if (i / 6 != size_t(7 * (n - 1) + 7)) holed.insert(holed.end(), m.indices.begin() + long(i), m.indices.begin() + long(i + 6));
  const HeightFieldNormals t = build_height_field_normals(m, holed, 0, 2, 1);
  ASSERT_GT(t.width, 0u);
  const glm::vec3 want = glm::normalize(glm::vec3(0.3f, 1.0f, 0.0f));
  EXPECT_NEAR(glm::length(texel(t, 15, 15) - want), 0.0f, 0.012f);  // the hole's centre
  // A vertex that is not a number (a broken file) costs its triangles, not the texture.
  scene::Mesh broken = m;
  broken.vertices[size_t(3 * n + 3)].position.x = NAN;
  const HeightFieldNormals b = build_height_field_normals(broken, broken.indices, 0, 2, 1);
  EXPECT_EQ(b.width, t.width);
  EXPECT_NEAR(glm::length(texel(b, 6, 6) - want), 0.0f, 0.012f);
  // No triangles, or no extent over the plane: no texture.
  EXPECT_EQ(build_height_field_normals(m, {}, 0, 2, 1).width, 0u);
  scene::Mesh line;
  line.vertices = {{{0, 0, 0}, {0, 1, 0}, {0, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0}}, {{2, 0, 0}, {0, 1, 0}, {0, 0}}};
  EXPECT_EQ(build_height_field_normals(line, {0, 1, 2}, 0, 2, 1).width, 0u);
}

}  // namespace
}  // namespace cumulo::render
