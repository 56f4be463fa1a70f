#pragma once
// The sample level's archipelago: a deterministic procedural heightfield (several islands, a volcanic
// peak of 200 m or more, beaches, sea floor), baked into a glTF binary (.glb) with a base-color texture
// (sand / grass / rock by height and slope) and a 40 km ocean quad at sea level.
//
// Determinism: only integer hashing and float arithmetic in a fixed order (no std:: distributions, no
// threads), so the same options give the same bytes on the same compiler and libm.
//
//   cumulo gen-terrain -o content/levels/sample/terrain.glb [--seed N] [--resolution N] [--texture N]
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo {
class CommandRegistry;
}

namespace cumulo::scene {

struct TerrainOptions {
  uint64_t seed = 1;
  uint32_t resolution = 257;     // grid vertices per side (>= 3); 257 -> 16 m spacing over 4096 m
  uint32_t texture_size = 512;   // base-color texture, texels per side (>= 4); 512 -> 8 m per texel
  float size_m = 4096.0f;        // the terrain square, centred on the origin (the cloudscape's 4096 m)
  float ocean_size_m = 40000.0f; // the ocean quad's side
  uint32_t max_tile_cells = 128; // cells per tile side, so tile vertices fit 16-bit indices
};

// One island of the archipelago (for the generator's report and for tests that place cameras).
struct Island {
  glm::vec2 center{0.0f};  // world x, z
  float radius = 0.0f;     // metres, where the shore roughly lies
  float height = 0.0f;     // nominal summit height above sea level, before detail noise
  float stretch = 1.0f;    // elongation along `axis` (>= 1)
  float axis = 0.0f;       // radians, direction of the long axis in the x-z plane
  bool volcano = false;    // the main island has a crater
};

// The continuous height function of the archipelago (metres above sea level at world x, z).
class Archipelago {
 public:
  explicit Archipelago(const TerrainOptions& options);
  float height(float x, float z) const;
  glm::vec3 normal(float x, float z, float eps = 4.0f) const;  // from central differences
  const std::vector<Island>& islands() const { return islands_; }
  const TerrainOptions& options() const { return options_; }

 private:
  TerrainOptions options_;
  std::vector<Island> islands_;
};

// Sampled on the grid: resolution x resolution heights, row j at z = -size/2 + j * spacing.
struct Heightfield {
  uint32_t resolution = 0;
  float size_m = 0.0f;
  std::vector<float> heights;
  float spacing() const { return size_m / float(resolution - 1); }
  float at(uint32_t i, uint32_t j) const { return heights[size_t(j) * resolution + i]; }
  glm::vec3 position(uint32_t i, uint32_t j) const;
  float sample(float x, float z) const;  // bilinear, clamped to the square: what the mesh shows
};

Heightfield sample_heightfield(const Archipelago& a);

struct TerrainReport {
  float min_height = 0.0f, max_height = 0.0f;
  glm::vec2 peak_xz{0.0f};
  float land_fraction = 0.0f;  // of grid vertices above sea level
  size_t terrain_vertices = 0, terrain_triangles = 0, tiles = 0;
  size_t bytes = 0;
  std::vector<Island> islands;
};

// The .glb file's bytes; fills `report` when given.
std::vector<uint8_t> build_terrain_glb(const TerrainOptions& options, TerrainReport* report = nullptr);

// Registers `cumulo gen-terrain`.
void register_scene_commands(CommandRegistry& registry);

}  // namespace cumulo::scene
