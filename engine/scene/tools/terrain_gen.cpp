// The sample archipelago: heights, colours, and the .glb that holds them.
//
// [index]  random numbers and noise  |  Archipelago (islands, height function)  |  Heightfield
//          |  base-color texture  |  meshes and the .glb
#include "engine/core/random.h"
#include "engine/scene/tools/terrain_gen.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/fbm.h"
#include "engine/core/png.h"
#include "engine/scene/tools/glb_writer.h"

namespace cumulo::scene {

namespace {

// ---- random numbers and noise -----------------------------------------------------------------------
using Rng = SplitMix64;  // engine/core/random.h

uint32_t hash2(int32_t x, int32_t y, uint32_t seed) {
  uint64_t h = (uint64_t(uint32_t(x)) * 0x9E3779B1ull) ^ (uint64_t(uint32_t(y)) * 0x85EBCA77ull) ^ (uint64_t(seed) << 32);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return uint32_t(h);
}

// 2D gradient noise (Perlin's, with 8 fixed gradients), roughly in [-1, 1].
float gradient_noise(float x, float y, uint32_t seed) {
  static const float kGrad[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1},
                                    {0.7071f, 0.7071f}, {-0.7071f, 0.7071f}, {0.7071f, -0.7071f}, {-0.7071f, -0.7071f}};
  float fx = std::floor(x), fy = std::floor(y);
  int32_t ix = int32_t(fx), iy = int32_t(fy);
  float tx = x - fx, ty = y - fy;
  auto dot_grad = [&](int32_t cx, int32_t cy, float dx, float dy) {
    const float* g = kGrad[hash2(cx, cy, seed) & 7];
    return g[0] * dx + g[1] * dy;
  };
  float n00 = dot_grad(ix, iy, tx, ty);
  float n10 = dot_grad(ix + 1, iy, tx - 1, ty);
  float n01 = dot_grad(ix, iy + 1, tx, ty - 1);
  float n11 = dot_grad(ix + 1, iy + 1, tx - 1, ty - 1);
  float ux = tx * tx * tx * (tx * (tx * 6 - 15) + 10);  // quintic fade: C2-continuous heights
  float uy = ty * ty * ty * (ty * (ty * 6 - 15) + 10);
  float a = n00 + (n10 - n00) * ux;
  float b = n01 + (n11 - n01) * ux;
  return 1.4142f * (a + (b - a) * uy);
}

// Lacunarity 2.03, not exactly 2, so octaves do not line up on the integer lattice.
constexpr float kLacunarity = 2.03f;

float fbm(float x, float y, int octaves, uint32_t seed) {
  return cumulo::fbm(octaves, 0.5f, kLacunarity,
                     [&](int o, float freq) { return gradient_noise(x * freq, y * freq, seed + uint32_t(o) * 1013u); });
}

// Ridged multifractal: sharp crests for the volcanic rock.
float ridged(float x, float y, int octaves, uint32_t seed) {
  return cumulo::fbm(octaves, 0.5f, kLacunarity, [&](int o, float freq) {
    float n = 1.0f - std::abs(gradient_noise(x * freq, y * freq, seed + 7919u + uint32_t(o) * 1013u));
    return n * n;
  });
}

float smoothstep(float e0, float e1, float x) {
  float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

constexpr float kSeaFloor = 45.0f;  // metres below sea level between islands
constexpr float kEdgeDrop = 60.0f;  // extra depth toward the square's edge, so no island is cut off

}  // namespace

// ---- Archipelago ------------------------------------------------------------------------------------
Archipelago::Archipelago(const TerrainOptions& options) : options_(options) {
  Rng rng{options.seed * 0x2545F4914F6CDD1Dull + 0x1234567ull};
  float half = 0.5f * options.size_m;
  float s = options.size_m / 4096.0f;  // sizes below are tuned for the 4096 m square
  // The main, volcanic island: the 200+ m peak of the Burning Shores brief (2023 talk: "that 200 meter
  // mountain top with clouds").
  Island main;
  float angle = rng.range(0.0f, 6.2831853f);
  float dist = rng.range(150.0f, 450.0f) * s;
  main.center = glm::vec2(std::cos(angle), std::sin(angle)) * dist;
  main.radius = rng.range(660.0f, 780.0f) * s;
  main.height = rng.range(290.0f, 330.0f);
  main.volcano = true;
  main.stretch = rng.range(1.0f, 1.3f);
  main.axis = rng.range(0.0f, 3.1415926f);
  islands_.push_back(main);
  int wanted = 6 + int(rng.uniform() * 2.0f);
  for (int tries = 0; tries < 1000 && int(islands_.size()) < wanted + 1; ++tries) {
    Island is;
    is.center = glm::vec2(rng.range(-0.66f, 0.66f), rng.range(-0.66f, 0.66f)) * half;
    is.radius = rng.range(170.0f, 480.0f) * s;
    is.height = rng.range(14.0f, 40.0f) + rng.uniform() * 0.25f * is.radius / s;
    is.stretch = rng.range(1.0f, 2.2f);
    is.axis = rng.range(0.0f, 3.1415926f);
    bool ok = true;
    for (auto& o : islands_)
      if (glm::distance(is.center, o.center) < 1.05f * (is.radius * is.stretch + o.radius * o.stretch) + 120.0f * s) ok = false;
    if (ok) islands_.push_back(is);
  }
}

float Archipelago::height(float x, float z) const {
  const uint32_t seed = uint32_t(options_.seed * 2654435761ull);
  float s = options_.size_m / 4096.0f;
  glm::vec2 p(x, z);
  // Domain warp at two scales: coastlines with bays, headlands and spits instead of ellipses.
  glm::vec2 warp(fbm(x / (700.0f * s) + 13.1f, z / (700.0f * s) - 7.7f, 4, seed + 11),
                 fbm(x / (700.0f * s) - 21.3f, z / (700.0f * s) + 3.9f, 4, seed + 23));
  glm::vec2 fine(fbm(x / (160.0f * s) + 5.3f, z / (160.0f * s) + 1.1f, 3, seed + 31),
                 fbm(x / (160.0f * s) - 2.9f, z / (160.0f * s) - 8.4f, 3, seed + 37));
  glm::vec2 q = p + warp * (380.0f * s) + fine * (45.0f * s);

  float bump = 0.0f;
  for (const Island& is : islands_) {
    // Distance in the island's own frame, its long axis stretched back to a circle.
    glm::vec2 d = q - is.center, ax(std::cos(is.axis), std::sin(is.axis));
    float along = glm::dot(d, ax) / is.stretch, across = ax.x * d.y - ax.y * d.x;
    float t = std::sqrt(along * along + across * across) / is.radius;
    // Profile exp(-k t^e) scaled so the shore (t = 1) lies at sea level: g(1) = D / (A + D).
    float k = std::log((is.height + kSeaFloor) / kSeaFloor);
    float e = is.volcano ? 1.4f : 2.0f;  // a volcano is a cone, small islands are domes
    float b = (is.height + kSeaFloor) * std::exp(-k * std::pow(t, e));
    if (is.volcano) b -= 70.0f * std::pow(1.0f - smoothstep(0.0f, 0.16f, t), 2.0f);  // the crater
    bump = std::max(bump, b);
  }
  float h = bump - kSeaFloor;

  // Rock detail grows with height; a little roughness everywhere.
  float rock = ridged(x / (380.0f * s), z / (380.0f * s), 5, seed + 101) - 0.45f;
  h += rock * 55.0f * smoothstep(8.0f, 140.0f, h);
  h += fbm(x / (110.0f * s), z / (110.0f * s), 3, seed + 202) * 2.5f;

  // Beaches: flatten the band around sea level (slope x0.35 within about +-2 m, back to x1 by 14 m).
  h *= 0.35f + 0.65f * smoothstep(2.0f, 14.0f, std::abs(h));

  float half = 0.5f * options_.size_m;
  float edge = std::max(std::abs(x), std::abs(z));
  h -= kEdgeDrop * smoothstep(0.78f * half, half, edge);
  return h;
}

glm::vec3 Archipelago::normal(float x, float z, float eps) const {
  float dx = height(x + eps, z) - height(x - eps, z);
  float dz = height(x, z + eps) - height(x, z - eps);
  return glm::normalize(glm::vec3(-dx, 2.0f * eps, -dz));
}

// ---- Heightfield ------------------------------------------------------------------------------------
glm::vec3 Heightfield::position(uint32_t i, uint32_t j) const {
  float half = 0.5f * size_m;
  return glm::vec3(-half + float(i) * spacing(), at(i, j), -half + float(j) * spacing());
}

float Heightfield::sample(float x, float z) const {
  float half = 0.5f * size_m;
  float fx = std::clamp((x + half) / spacing(), 0.0f, float(resolution - 1));
  float fz = std::clamp((z + half) / spacing(), 0.0f, float(resolution - 1));
  uint32_t i = std::min(uint32_t(fx), resolution - 2), j = std::min(uint32_t(fz), resolution - 2);
  float tx = fx - float(i), tz = fz - float(j);
  float a = at(i, j) + (at(i + 1, j) - at(i, j)) * tx;
  float b = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * tx;
  return a + (b - a) * tz;
}

Heightfield sample_heightfield(const Archipelago& a) {
  const auto& o = a.options();
  if (o.resolution < 3) fail("terrain resolution %u is too small (at least 3)", o.resolution);
  Heightfield hf;
  hf.resolution = o.resolution;
  hf.size_m = o.size_m;
  hf.heights.resize(size_t(o.resolution) * o.resolution);
  float half = 0.5f * o.size_m, step = hf.spacing();
  for (uint32_t j = 0; j < o.resolution; ++j)
    for (uint32_t i = 0; i < o.resolution; ++i)
      hf.heights[size_t(j) * o.resolution + i] = a.height(-half + float(i) * step, -half + float(j) * step);
  return hf;
}

namespace {

glm::vec3 grid_normal(const Heightfield& hf, uint32_t i, uint32_t j) {
  uint32_t i0 = i > 0 ? i - 1 : i, i1 = std::min(i + 1, hf.resolution - 1);
  uint32_t j0 = j > 0 ? j - 1 : j, j1 = std::min(j + 1, hf.resolution - 1);
  float dx = (hf.at(i1, j) - hf.at(i0, j)) / (float(i1 - i0) * hf.spacing());
  float dz = (hf.at(i, j1) - hf.at(i, j0)) / (float(j1 - j0) * hf.spacing());
  return glm::normalize(glm::vec3(-dx, 1.0f, -dz));
}

// ---- base-color texture -----------------------------------------------------------------------------
// Colours are sRGB (a glTF base-color texture is sRGB-encoded). They follow the mesh, not the continuous
// height function, so the sand line lies where the geometry meets the sea.
std::vector<uint8_t> bake_texture(const Archipelago& a, const Heightfield& hf, uint32_t size) {
  const glm::vec3 kWetSand(0.62f, 0.55f, 0.41f), kSand(0.86f, 0.78f, 0.58f), kGrass(0.30f, 0.44f, 0.16f),
      kDryGrass(0.52f, 0.50f, 0.27f), kRock(0.42f, 0.38f, 0.34f), kBasalt(0.24f, 0.22f, 0.21f);
  const uint32_t seed = uint32_t(a.options().seed * 40503ull + 17);
  float half = 0.5f * hf.size_m, texel = hf.size_m / float(size), eps = hf.spacing();
  std::vector<uint8_t> rgb(size_t(size) * size * 3);
  for (uint32_t ty = 0; ty < size; ++ty) {
    for (uint32_t tx = 0; tx < size; ++tx) {
      // Texel (tx, ty) covers uv ((tx + .5) / size, (ty + .5) / size): u along +X, v along +Z.
      float x = -half + (float(tx) + 0.5f) * texel, z = -half + (float(ty) + 0.5f) * texel;
      float h = hf.sample(x, z);
      float dx = hf.sample(x + eps, z) - hf.sample(x - eps, z);
      float dz = hf.sample(x, z + eps) - hf.sample(x, z - eps);
      float up = glm::normalize(glm::vec3(-dx, 2.0f * eps, -dz)).y;  // cos(slope)
      float n1 = fbm(x / 60.0f, z / 60.0f, 3, seed), n2 = fbm(x / 15.0f, z / 15.0f, 2, seed + 5);

      float sand_line = 3.5f + 2.0f * n1;
      glm::vec3 c = glm::mix(kWetSand, kSand, smoothstep(-1.5f, 0.8f, h));
      glm::vec3 veg = glm::mix(kGrass, kDryGrass, smoothstep(40.0f, 170.0f, h + 40.0f * n1));
      c = glm::mix(c, veg, smoothstep(sand_line, sand_line + 2.5f, h));
      // Rock on steep ground (slope over ~32 degrees) and above the tree line; dark basalt near the summit.
      float steep = smoothstep(0.88f, 0.78f, up);
      float high = smoothstep(170.0f, 230.0f, h + 25.0f * n1);
      glm::vec3 rock = glm::mix(kRock, kBasalt, smoothstep(150.0f, 260.0f, h));
      c = glm::mix(c, rock, std::max(steep, high) * smoothstep(1.0f, 4.0f, h));
      c *= 1.0f + 0.10f * n2;  // texel-scale variation so flat areas are not a single colour
      uint8_t* out = &rgb[(size_t(ty) * size + tx) * 3];
      for (int k = 0; k < 3; ++k) out[k] = uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    }
  }
  return rgb;
}

}  // namespace

// ---- meshes and the .glb ----------------------------------------------------------------------------
std::vector<uint8_t> build_terrain_glb(const TerrainOptions& o, TerrainReport* report) {
  if (o.texture_size < 4 || o.texture_size > 8192) fail("terrain texture size %u out of range 4..8192", o.texture_size);
  if (o.resolution > 8193) fail("terrain resolution %u out of range 3..8193", o.resolution);
  if (o.max_tile_cells < 1) fail("terrain tiles need at least one cell");
  if (!(o.size_m > 0.0f) || !(o.ocean_size_m >= o.size_m)) fail("terrain size and ocean size must be positive, ocean >= terrain");
  Archipelago arch(o);
  Heightfield hf = sample_heightfield(arch);

  GlbWriter w;
  auto& j = w.json();
  const uint32_t cells = o.resolution - 1;
  const uint32_t tile_cells = std::min(o.max_tile_cells, cells);
  const uint32_t tiles = (cells + tile_cells - 1) / tile_cells;
  nlohmann::json prims = nlohmann::json::array();
  size_t vertices = 0, triangles = 0;
  for (uint32_t tz = 0; tz < tiles; ++tz) {
    for (uint32_t tx = 0; tx < tiles; ++tx) {
      uint32_t i0 = tx * tile_cells, i1 = std::min(i0 + tile_cells, cells);
      uint32_t j0 = tz * tile_cells, j1 = std::min(j0 + tile_cells, cells);
      uint32_t nx = i1 - i0 + 1, nz = j1 - j0 + 1;
      std::vector<glm::vec3> pos, nor;
      std::vector<glm::vec2> uv;
      for (uint32_t jj = j0; jj <= j1; ++jj) {
        for (uint32_t ii = i0; ii <= i1; ++ii) {
          pos.push_back(hf.position(ii, jj));
          nor.push_back(grid_normal(hf, ii, jj));  // from the whole grid, so tile seams match
          uv.emplace_back(float(ii) / float(cells), float(jj) / float(cells));
        }
      }
      // Two counter-clockwise (seen from +Y) triangles per cell.
      std::vector<uint32_t> idx;
      for (uint32_t c = 0; c + 1 < nz; ++c) {
        for (uint32_t r = 0; r + 1 < nx; ++r) {
          uint32_t v00 = c * nx + r, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
          idx.insert(idx.end(), {v00, v01, v10, v10, v01, v11});
        }
      }
      int ind;
      if (pos.size() < 65535) {  // 0xFFFF is reserved (primitive restart), glTF 2.0 spec 3.7.2.1
        std::vector<uint16_t> idx16(idx.begin(), idx.end());
        ind = w.add_indices_u16(idx16);
      } else {
        ind = w.add_indices_u32(idx);
      }
      int p = w.add_vec3(pos, true), n = w.add_vec3(nor, false), t = w.add_vec2(uv);
      prims.push_back({{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}}, {"indices", ind},
                       {"material", 0}, {"mode", 4}});
      vertices += pos.size();
      triangles += idx.size() / 3;
    }
  }

  // The ocean: one quad at sea level, far past the terrain, so the horizon is water in every direction.
  float oh = 0.5f * o.ocean_size_m;
  std::vector<glm::vec3> opos = {{-oh, 0, -oh}, {oh, 0, -oh}, {oh, 0, oh}, {-oh, 0, oh}};
  std::vector<glm::vec3> onor(4, glm::vec3(0, 1, 0));
  std::vector<glm::vec2> ouv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<uint16_t> oidx = {0, 3, 1, 1, 3, 2};
  int oi = w.add_indices_u16(oidx);
  int op = w.add_vec3(opos, true), on = w.add_vec3(onor, false), ot = w.add_vec2(ouv);

  std::vector<uint8_t> rgb = bake_texture(arch, hf, o.texture_size);
  std::vector<uint8_t> png = encode_png(rgb.data(), o.texture_size, o.texture_size, 3);
  int image = w.add_png_image(png, "terrain_base_color");

  j["meshes"] = {{{"name", "terrain"}, {"primitives", prims}},
                 {{"name", "ocean"},
                  {"primitives", {{{"attributes", {{"POSITION", op}, {"NORMAL", on}, {"TEXCOORD_0", ot}}},
                                   {"indices", oi}, {"material", 1}, {"mode", 4}}}}}};
  j["materials"] = {
      {{"name", "terrain"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.9}}}},
      {{"name", "ocean"},
       {"pbrMetallicRoughness",
        {{"baseColorFactor", {0.02, 0.12, 0.20, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.15}}}}};
  j["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};  // linear, clamp
  j["textures"] = {{{"sampler", 0}, {"source", image}, {"name", "terrain_base_color"}}};
  j["nodes"] = {{{"name", "terrain"}, {"mesh", 0}}, {{"name", "ocean"}, {"mesh", 1}}};
  j["scenes"] = {{{"name", "archipelago"}, {"nodes", {0, 1}}}};
  j["scene"] = 0;
  j["extras"] = {{"seed", o.seed}, {"resolution", o.resolution}, {"size_m", o.size_m}, {"texture_size", o.texture_size}};
  std::vector<uint8_t> bytes = w.finish();

  if (report) {
    report->min_height = *std::min_element(hf.heights.begin(), hf.heights.end());
    auto top = std::max_element(hf.heights.begin(), hf.heights.end());
    report->max_height = *top;
    size_t k = size_t(top - hf.heights.begin());
    glm::vec3 peak = hf.position(uint32_t(k % o.resolution), uint32_t(k / o.resolution));
    report->peak_xz = glm::vec2(peak.x, peak.z);
    report->land_fraction =
        float(std::count_if(hf.heights.begin(), hf.heights.end(), [](float h) { return h > 0.0f; })) / float(hf.heights.size());
    report->terrain_vertices = vertices;
    report->terrain_triangles = triangles;
    report->tiles = size_t(tiles) * tiles;
    report->bytes = bytes.size();
    report->islands = arch.islands();
  }
  return bytes;
}

}  // namespace cumulo::scene
