#pragma once
// A cloudscape recipe ("frankencloudscape", 2023 talk "Atlas" and the 2011 SmogVox talk): a JSON list
// of edits applied in order to one signed distance field, plus where the baked box sits in the world.
//
// Index:  Transform  Erosion  Shear  Particle  Edit (kinds and ops)  ProfileParams  SliceSpec  Recipe
//         load_recipe / parse_recipe_text
//
// Axes: the engine's, Y up, metres (x, z horizontal). The bake grid and every .nvdf it writes use the
// same axis order: texel (i, j, k) is world (x, y, z), so a 4096 m x 512 m (up) x 4096 m box at 8 m is
// a 512 x 64 x 512 volume -- the talk's "512 x 512 x 64" with its Z-up swapped to our Y-up; a volume
// "z slice" is therefore a vertical layer of constant world z. The box is `bounds` in world space:
// the cloudscape is placed where the recipe says, no further transform.
//
// JSON shape (content/schemas/cloudscape.schema.json is the reference):
//   { "name": "...", "seed": 7, "voxel_size": 8, "bounds": {"min": [x,y,z], "max": [x,y,z]},
//     "defaults": {"detail_type": 0.5, "density_scale": 1.0, "coverage": 0.0},
//     "profile": {"depth": 96, "exponent": 1.0},
//     "edits": [ { "type": "sphere|metaball|ellipsoid|box|capsule|mesh|particles|volume|group",
//                  "op": "union|subtract|intersect", "blend": 40,
//                  "position": [..], "rotation": [deg x, deg y, deg z], "scale": s | [sx, sy, sz],
//                  "shear": [sx, sz], "erode": {"amplitude": 30, "frequency": 0.01, "octaves": 3},
//                  "detail_type": 0.8, "density_scale": 0.9, "coverage": 0.6, ...shape parameters... } ],
//     "slices": {"heights": [..], "vertical": [{"name": "hero", "axis": "x", "at": 120}]} }
// A "grown" edit places a cloud grown by the cloud-formation simulation (grow/grow_spec.h): its "spec"
// (a grow spec beside the recipe), "attributes": "simulated" (default: SDF, detail type, density
// scale and a thickness-following profile depth from the simulation, grow/grown_attributes.h) or
// "constant" (the faithful per-edit detail_type / density_scale and the recipe's profile depth).
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/core/enum_names.h"

namespace cumulo::clouds::bake {

struct Aabb {
  glm::vec3 min{1e30f};
  glm::vec3 max{-1e30f};
  bool empty() const { return min.x > max.x; }
  void add(glm::vec3 p) { min = glm::min(min, p), max = glm::max(max, p); }
  void add(const Aabb& b) {
    if (!b.empty()) add(b.min), add(b.max);
  }
  Aabb expanded(float m) const { return empty() ? *this : Aabb{min - m, max + m}; }
  bool contains(glm::vec3 p) const {
    return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
  }
};

// Parent space -> local space: p_local = inverse(rotation) * (p - position) / scale. Non-uniform
// scale is the recipe's squash/stretch; distances come back scaled by the smallest scale factor
// (a lower bound of the true distance).
struct Transform {
  glm::vec3 position{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  glm::vec3 to_local(glm::vec3 p) const { return (glm::inverse(rotation) * (p - position)) / scale; }
  glm::vec3 to_parent(glm::vec3 p) const { return rotation * (p * scale) + position; }
  float min_scale() const { return std::min(scale.x, std::min(scale.y, scale.z)); }
};

// Noise erosion: the edit's distance grows by amplitude * n, n in [0, 1] an fBm of gradient noise in
// world space at `frequency` cycles per metre. It only ever removes cloud (the talk's "erosion").
struct Erosion {
  float amplitude = 0.0f;  // metres
  float frequency = 0.0f;  // 1 / metres
  int octaves = 3;
  bool enabled() const { return amplitude > 0.0f && frequency > 0.0f; }
};

// Wind shear: the edit's shape is displaced horizontally by `per_metre` metres for every metre above
// its own position (a height-dependent skew, as the 2017 talk skews clouds downwind with height).
struct Shear {
  glm::vec2 per_metre{0.0f};  // (x, z)
  bool enabled() const { return per_metre.x != 0.0f || per_metre.y != 0.0f; }
};

struct Particle {
  glm::vec3 center;
  float radius;
};

struct ParticleBins;  // compose.h
class GridSdf;  // grid_sdf.h: a sampled distance grid (a voxelized glTF mesh or an imported .nvdf)
}  // namespace cumulo::clouds::bake
namespace cumulo::clouds::grow {
struct GrownModeling;  // grow/grown_attributes.h
}
namespace cumulo::clouds::bake {

enum class EditKind { Sphere, Ellipsoid, Box, Capsule, Mesh, Particles, Volume, Group, Grown };
// The recipe's "type" names ("metaball": a sphere that blends by default; a kind's name is its first row).
inline constexpr std::array kEditKindNames{
    EnumName<EditKind>{EditKind::Sphere, "sphere"},       EnumName<EditKind>{EditKind::Sphere, "metaball"},
    EnumName<EditKind>{EditKind::Ellipsoid, "ellipsoid"}, EnumName<EditKind>{EditKind::Box, "box"},
    EnumName<EditKind>{EditKind::Capsule, "capsule"},     EnumName<EditKind>{EditKind::Mesh, "mesh"},
    EnumName<EditKind>{EditKind::Particles, "particles"}, EnumName<EditKind>{EditKind::Volume, "volume"},
    EnumName<EditKind>{EditKind::Group, "group"},         EnumName<EditKind>{EditKind::Grown, "grown"}};
enum class EditOp { Union, Subtract, Intersect };
inline constexpr std::array kEditOpNames{EnumName<EditOp>{EditOp::Union, "union"}, EnumName<EditOp>{EditOp::Subtract, "subtract"},
                                         EnumName<EditOp>{EditOp::Intersect, "intersect"}};

struct Edit {
  std::string name;       // optional, for slices and messages
  std::string json_path;  // "$.edits[3]" for messages
  EditKind kind = EditKind::Sphere;
  EditOp op = EditOp::Union;
  Transform transform;
  float blend = 0.0f;  // soft-min blend radius, metres (parent space)
  float detail_type = 0.5f;    // 0 = wispy, 1 = billowy (2023 talk)
  float density_scale = 1.0f;  // multiplies density after the up-rez
  // Coverage threshold 0..1: the weather coverage this edit's cloud needs (fully present at coverage >=
  // threshold, gone at threshold - CLOUD_COVERAGE_RAMP and below: shaders/shared/cloud_params.h). 0: at any
  // coverage. Inherited from the group or the recipe's defaults, like detail_type.
  float coverage = 0.0f;
  float profile_depth = 96.0f; // metres below the surface where the profile reaches 1 (the recipe's by default)
  Erosion erosion;
  Shear shear;

  // Shape parameters, in local space (metres before scale).
  float radius = 0.0f;                  // sphere, capsule
  glm::vec3 radii{0.0f};                // ellipsoid
  glm::vec3 half_extents{0.0f};         // box
  float rounding = 0.0f;                // box edge radius
  glm::vec3 a{0.0f}, b{0.0f};           // capsule segment
  std::vector<Particle> particles;      // particles
  float particle_blend = 0.0f;          // soft-min radius between particles
  std::shared_ptr<const GridSdf> grid;  // mesh, volume: distances in local space
  std::string source;                   // mesh/volume file, as resolved
  std::vector<Edit> children;           // group
  std::shared_ptr<const grow::GrownModeling> grown;  // grown: attributes in local space
  bool grown_simulated = true;          // grown: attributes from the simulation (false: constant, the faithful form)
  uint64_t grown_key = 0;               // grown: the spec's key (spec content + solver version)
  uint32_t noise_seed = 0;              // erosion noise stream: hash of (recipe seed, json_path)
  std::shared_ptr<const ParticleBins> bins;        // particles: spatial hash, built by finalize_edits()

  // Derived by finalize_edits(): the box in parent space where the edit can matter.
  Aabb local_bounds;   // the shape's own box in local space (no margins)
  Aabb parent_bounds;  // local_bounds transformed, sheared, expanded by blend + erosion + band
};

// Dimensional profile from the signed distance (2023 talk: "generated from a signed-distance field of
// the cloud to ensure that we get a gradient from outside to inside"): profile = saturate(depth /
// `depth`) ^ `exponent`, depth = -sdf (metres below the surface).
struct ProfileParams {
  float depth = 96.0f;
  float exponent = 1.0f;
};

struct VerticalSlice {
  std::string name;
  int axis = 0;      // 0: plane of constant x, 2: plane of constant z
  float at = 0.0f;   // world coordinate of that plane
  float from = 0.0f, to = 0.0f;  // optional crop along the image's horizontal axis (world), from < to
};

struct SliceSpec {
  std::vector<float> heights;  // world y of horizontal slices
  std::vector<VerticalSlice> vertical;
};

struct Recipe {
  std::string file;  // for messages
  std::string name;
  uint64_t seed = 1;
  glm::vec3 bounds_min{-2048.0f, 0.0f, -2048.0f};  // default: the talk's 4096 x 512 x 4096 m
  glm::vec3 bounds_max{2048.0f, 512.0f, 2048.0f};
  float voxel_size = 8.0f;
  float default_detail_type = 0.5f;
  float default_density_scale = 1.0f;
  float default_coverage = 0.0f;
  ProfileParams profile;
  std::vector<Edit> edits;
  SliceSpec slices;
};

// Parses and validates a recipe; every error names the file and the JSON path
// ("cloudscape.json: $.edits[4].radius: expected a number > 0"). Relative mesh/volume paths resolve
// against the recipe's folder.
struct RecipeOptions {
  std::optional<uint64_t> seed;  // overrides the recipe's "seed" (particles and noise derive from it)
  bool allow_files = true;       // false: mesh, volume and grown edits are refused (fuzzing untrusted text)
  bool grown_constant = false;   // every grown edit takes the constant (faithful) attributes
  bool grow_progress = true;     // a progress line when a grown cloud must be grown first
};
Recipe load_recipe(const std::filesystem::path& path, const RecipeOptions& options = {});
Recipe parse_recipe_text(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                         const RecipeOptions& options = {});

// Computes every edit's bounds; `band` (metres) is how far from a surface voxels still need exact
// values (a few voxels). Called by the parsers; call again after editing a Recipe in code.
void finalize_edits(Recipe& recipe, float band);

// The attributes the recipe gives every edit that sets none (its defaults and profile depth), as an Edit.
Edit recipe_defaults(const Recipe& recipe);
inline const char* edit_kind_name(EditKind k) { return name_of(kEditKindNames, k); }

}  // namespace cumulo::clouds::bake
