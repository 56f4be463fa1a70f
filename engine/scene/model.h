#pragma once
// CPU-side models: what a glTF file becomes after loading. Plain data, no GPU objects; the renderer
// uploads them (one vertex/index buffer per Mesh, one image per Texture).
//
// [index]  Bounds  Vertex  Mesh  Texture  Material  MeshInstance  Model
//
// Conventions: metres, right-handed, Y up (glTF's own), counter-clockwise front faces.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::scene {

// Axis-aligned box; empty() until something is added.
struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{-std::numeric_limits<float>::max()};

  bool empty() const { return min.x > max.x; }
  void add(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void add(const Bounds& b) {
    if (!b.empty()) add(b.min), add(b.max);
  }
  glm::vec3 center() const { return (min + max) * 0.5f; }
  glm::vec3 size() const { return empty() ? glm::vec3(0.0f) : max - min; }
  Bounds transformed(const glm::mat4& m) const;  // box around the 8 transformed corners
};

// 32 bytes, tightly packed: the layout the geometry pass binds (location 0/1/2).
struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};
static_assert(sizeof(Vertex) == 32, "Vertex is bound as a tightly packed 32-byte stride");

// One glTF primitive (triangle list), indices widened to 32 bits.
struct Mesh {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;  // triangle list, 3 per triangle
  int material = -1;              // index into Model::materials, -1 = default material
  Bounds bounds;                  // in mesh space
  bool generated_normals = false; // the file had no NORMAL attribute
};

enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };

// Decoded RGBA8 image plus its glTF sampler state.
struct Texture {
  std::string name;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4 bytes, row 0 = top of the image (glTF uv (0,0))
  bool srgb = true;           // base-color textures are sRGB-encoded (glTF 2.0 spec 3.9.2)
  Wrap wrap_u = Wrap::Repeat, wrap_v = Wrap::Repeat;
  bool linear_filter = true;  // false when the glTF sampler asks for NEAREST magnification
};

enum class AlphaMode { Opaque, Mask, Blend };

struct Material {
  std::string name;
  glm::vec4 base_color_factor{1.0f};  // linear RGBA, multiplies the texture
  int base_color_texture = -1;        // index into Model::textures, -1 = none
  float metallic = 1.0f;              // glTF defaults
  float roughness = 1.0f;
  glm::vec3 emissive{0.0f};
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
};

// A mesh placed in the model's space (the node hierarchy flattened).
struct MeshInstance {
  uint32_t mesh = 0;           // index into Model::meshes
  glm::mat4 world{1.0f};       // node's world matrix (model space)
  std::string node;            // name of the glTF node, for debugging
};

struct Model {
  std::filesystem::path source;  // the file it was loaded from
  std::vector<Mesh> meshes;
  std::vector<Texture> textures;
  std::vector<Material> materials;
  std::vector<MeshInstance> instances;
  Bounds bounds;  // of every instance, in model space

  size_t vertex_count() const;
  size_t triangle_count() const;
  // The instances whose mesh uses the material named `name` (empty if none).
  std::vector<const MeshInstance*> instances_with_material(const std::string& name) const;
};

}  // namespace cumulo::scene
