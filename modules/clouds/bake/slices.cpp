// Cross-section PNGs of a bake (`cumulo bake ... --slices DIR`): what a person looks at to see that
// the recipe reads as intended.
#include <algorithm>
#include <cmath>
#include <functional>

#include "engine/core/error.h"
#include "engine/core/png.h"
#include "modules/clouds/bake/bake.h"

namespace cumulo::clouds::bake {

namespace {

glm::vec3 mix3(glm::vec3 a, glm::vec3 b, float t) { return a + (b - a) * t; }

// Inside: blues by depth; outside: cream to brown on a log scale; thin contours every 64 m; the
// surface (sdf = 0) in black.
glm::vec3 sdf_color(float d, float voxel) {
  glm::vec3 c;
  if (d < 0.0f) {
    c = mix3({0.60f, 0.80f, 1.00f}, {0.05f, 0.12f, 0.50f}, std::min(-d / 160.0f, 1.0f));
  } else {
    c = mix3({1.00f, 0.96f, 0.86f}, {0.40f, 0.16f, 0.05f}, std::min(std::log2(1.0f + d / 8.0f) / 9.0f, 1.0f));
  }
  float m = std::fmod(std::abs(d), 64.0f);
  if (std::min(m, 64.0f - m) < 0.35f * voxel) c *= 0.75f;
  if (std::abs(d) < 0.5f * voxel) c = glm::vec3(0.0f);
  return c;
}

glm::vec3 profile_color(float p) {
  if (p <= 0.0f) return {0.08f, 0.08f, 0.12f};
  return glm::vec3(0.2f + 0.8f * p);
}

void put(std::vector<uint8_t>& img, size_t i, glm::vec3 c) {
  for (int k = 0; k < 3; ++k) img[3 * i + k] = static_cast<uint8_t>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
}

struct Plane {
  std::string name;
  uint32_t w, h;
  uint32_t scale = 1;  // nearest-neighbour upscale so thin vertical slices stay readable
  // texel (u, v) of the image (v = 0 at the top) -> voxel index
  std::function<size_t(uint32_t, uint32_t)> voxel;
};

}  // namespace

std::vector<std::filesystem::path> write_slices(const Recipe& recipe, const BakeResult& r,
                                                const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) fail("%s: cannot create the slices folder: %s", dir.string().c_str(), ec.message().c_str());
  const BakeGrid& g = r.grid;
  const glm::uvec3 d = g.dims;
  std::vector<Plane> planes;

  std::vector<float> heights = recipe.slices.heights;
  if (heights.empty()) {
    float lo = g.bounds_min().y, hi = g.bounds_max().y;
    heights = {lo + 0.25f * (hi - lo), lo + 0.5f * (hi - lo), lo + 0.75f * (hi - lo)};
  }
  for (float h : heights) {
    int y = static_cast<int>(std::floor((h - g.bounds_min().y) / g.spacing.y));
    if (y < 0 || y >= static_cast<int>(d.y)) continue;
    // Looking down: +x to the right, +z down the image.
    planes.push_back({strf("y%04d", static_cast<int>(std::lround(h))), d.x, d.z, 1,
                      [&g, y](uint32_t u, uint32_t v) { return g.index(u, uint32_t(y), v); }});
  }
  std::vector<VerticalSlice> verticals = recipe.slices.vertical;
  if (verticals.empty()) {
    glm::vec3 c = 0.5f * (g.bounds_min() + g.bounds_max());
    verticals = {{"center_x", 0, c.x}, {"center_z", 2, c.z}};
  }
  for (const VerticalSlice& vs : verticals) {
    int a = vs.axis;
    int k = static_cast<int>(std::floor((vs.at - g.bounds_min()[a]) / g.spacing[a]));
    if (k < 0 || k >= static_cast<int>(d[a])) continue;
    uint32_t ny = d.y;
    int ha = a == 0 ? 2 : 0;  // the image's horizontal axis: z for planes of constant x, x otherwise
    uint32_t u0 = 0, u1 = d[ha];
    if (vs.to > vs.from) {
      u0 = static_cast<uint32_t>(std::clamp((vs.from - g.bounds_min()[ha]) / g.spacing[ha], 0.0f, float(d[ha] - 1)));
      u1 = static_cast<uint32_t>(std::clamp((vs.to - g.bounds_min()[ha]) / g.spacing[ha], float(u0 + 1), float(d[ha])));
    }
    uint32_t scale = std::clamp(256u / std::max(ny, 1u), 1u, 4u);
    if (a == 0)  // plane of constant x: +z to the right, up is up
      planes.push_back({"v_" + vs.name, u1 - u0, ny, scale,
                        [&g, k, ny, u0](uint32_t u, uint32_t v) { return g.index(uint32_t(k), ny - 1 - v, u0 + u); }});
    else
      planes.push_back({"v_" + vs.name, u1 - u0, ny, scale,
                        [&g, k, ny, u0](uint32_t u, uint32_t v) { return g.index(u0 + u, ny - 1 - v, uint32_t(k)); }});
  }

  std::vector<std::filesystem::path> written;
  const float voxel = std::min(g.spacing.x, g.spacing.z);
  for (const Plane& p : planes) {
    const uint32_t W = p.w * p.scale, H = p.h * p.scale;
    std::vector<uint8_t> prof(size_t(W) * H * 3), sdf(prof.size()), model(prof.size());
    for (uint32_t v = 0; v < H; ++v)
      for (uint32_t u = 0; u < W; ++u) {
        size_t i = p.voxel(u / p.scale, v / p.scale), o = size_t(v) * W + u;
        put(prof, o, profile_color(r.modeling[3 * i]));
        put(sdf, o, sdf_color(r.field[i], voxel));
        float pr = r.modeling[3 * i];
        put(model, o, pr > 0.0f ? glm::vec3(pr, r.modeling[3 * i + 1], r.modeling[3 * i + 2]) : glm::vec3(0.0f));
      }
    for (auto& [suffix, img] : {std::pair<const char*, const std::vector<uint8_t>*>{"profile", &prof},
                                {"sdf", &sdf},
                                {"modeling", &model}}) {
      std::filesystem::path path = dir / (p.name + "_" + suffix + ".png");
      cumulo::write_png(path, img->data(), W, H, 3);
      written.push_back(path);
    }
  }
  return written;
}

}  // namespace cumulo::clouds::bake
