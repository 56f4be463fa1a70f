#include "modules/clouds/bake/recipe.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <unordered_map>

#include "engine/core/random.h"
#include "engine/core/error.h"
#include "engine/core/hash.h"
#include "engine/core/json.h"
#include "engine/core/message.h"
#include "modules/clouds/bake/compose.h"
#include "modules/clouds/bake/grid_sdf.h"
#include "modules/clouds/bake/grow/grow_cache.h"
#include "modules/clouds/bake/grow/grown_attributes.h"

namespace cumulo::clouds::bake {

namespace {

constexpr float kMaxCoord = 1.0e6f;  // metres; anything larger is a typo
// Smallest particle radius and scale: far below any voxel (>= 0.25 m), far above the tiny values
// (1e-40) whose reciprocals overflow a float and empty the bake silently.
constexpr float kMinSize = 1.0e-3f;
constexpr size_t kMaxEdits = 100000;
constexpr size_t kMaxParticles = 1000000;
constexpr int kMaxDepth = 16;  // group nesting

struct Ctx {
  std::filesystem::path base_dir;
  bool allow_files = true;
  bool grown_constant = false;
  bool grow_progress = true;
  size_t edit_count = 0;
  size_t particle_count = 0;
};

// Unknown members are errors: a misspelt "radus" would otherwise silently bake a default.
void check_keys(const JsonView& v, const std::set<std::string>& allowed) {
  for (const std::string& k : v.keys())
    if (!allowed.count(k)) v[k].fail("unknown member " + quote(k, 64));
}

float positive(const JsonView& v, float hi = kMaxCoord) {
  float f = v.as<float>();
  if (!(f > 0.0f) || f > hi) v.fail(strf("expected a number in (0, %g], got %g", hi, f));
  return f;
}
float non_negative(const JsonView& v, float hi = kMaxCoord) { return v.as_float_in(0.0f, hi); }
glm::vec3 coord3(const JsonView& v) {
  glm::vec3 p = v.as_vec3();
  for (int i = 0; i < 3; ++i)
    if (std::abs(p[i]) > kMaxCoord) v.at(i).fail(strf("coordinate %g is out of range (|x| <= %g m)", p[i], kMaxCoord));
  return p;
}
glm::vec3 positive3(const JsonView& v) {
  glm::vec3 p = v.as_vec3();
  for (int i = 0; i < 3; ++i) positive(v.at(i));
  return p;
}

Transform parse_transform(const JsonView& e) {
  Transform t;
  if (e.has("position")) t.position = coord3(e["position"]);
  if (e.has("rotation")) {
    glm::vec3 deg = e["rotation"].as_vec3();
    for (int i = 0; i < 3; ++i)
      if (std::abs(deg[i]) > 3600.0f) e["rotation"].at(i).fail("rotation angle out of range (degrees)");
    t.rotation = glm::quat(glm::radians(deg));  // XYZ Euler angles in degrees (glm's order)
  }
  if (e.has("scale")) {
    JsonView s = e["scale"];
    auto factor = [](const JsonView& f) {
      const float x = f.as<float>();
      if (!(x >= kMinSize && x <= 1000.0f)) f.fail(strf("scale %g is outside %g..1000", x, kMinSize));
      return x;
    };
    if (s.raw().is_number()) {
      t.scale = glm::vec3(factor(s));
    } else {
      t.scale = s.as_vec3();
      for (int i = 0; i < 3; ++i) factor(s.at(i));
    }
  }
  return t;
}

// Uniformly distributed points inside an ellipsoid, deterministic from (seed, edit path).
std::vector<Particle> generate_particles(const JsonView& g, uint64_t seed) {
  check_keys(g, {"count", "radii", "radius", "seed", "flatten_bottom"});
  uint32_t count = g["count"].as<uint32_t>();
  if (count == 0 || count > 100000) g["count"].fail("expected 1..100000 particles");
  glm::vec3 radii = positive3(g["radii"]);
  glm::vec2 r = g["radius"].as_vec2();
  if (!(r.x >= kMinSize) || r.y < r.x || r.y > kMaxCoord)
    g["radius"].fail(strf("expected [min, max] radii with %g <= min <= max <= %g", kMinSize, kMaxCoord));
  SplitMix64 rng{g.get<uint64_t>("seed", 0) ^ (seed * 0x9E3779B97F4A7C15ull)};
  bool flat = g.get<bool>("flatten_bottom", false);
  auto next = [&rng]() { return rng.uniform(); };
  std::vector<Particle> out;
  out.reserve(count);
  while (out.size() < count) {
    glm::vec3 u{next() * 2.0f - 1.0f, next() * 2.0f - 1.0f, next() * 2.0f - 1.0f};
    float rad = r.x + (r.y - r.x) * next();
    if (glm::dot(u, u) > 1.0f) continue;
    if (flat && u.y < 0.0f) u.y *= 0.25f;  // a flatter base, as cumulus bases are
    out.push_back({u * radii, rad});
  }
  return out;
}

// A grown cloud's attributes, derived once per process for each spec key (a recipe places one grown
// cloud many times, rotated and scaled: frankenclouding).
std::shared_ptr<const grow::GrownModeling> grown_modeling_for(const std::filesystem::path& spec_path, bool progress,
                                                              uint64_t* key) {
  static std::mutex mutex;
  static std::unordered_map<uint64_t, std::shared_ptr<const grow::GrownModeling>> cache;
  const grow::GrowSpec spec = grow::load_grow_spec(spec_path);
  *key = spec.key;
  std::lock_guard lock(mutex);
  auto it = cache.find(spec.key);
  if (it != cache.end()) return it->second;
  const grow::ResolvedGrown where = grow::resolve_grown(spec, spec_path, progress);
  auto m = grow::derive_modeling(grow::load_grown(where.dir / "grown.nvdf"));
  cache.emplace(spec.key, m);
  return m;
}

Edit parse_edit(const JsonView& e, Ctx& ctx, const Edit& parent_defaults, uint64_t seed, int depth) {
  if (depth > kMaxDepth) e.fail(strf("groups nested deeper than %d", kMaxDepth));
  if (++ctx.edit_count > kMaxEdits) e.fail(strf("more than %zu edits", kMaxEdits));
  if (!e.is_object()) e.fail("expected an edit object");
  Edit out;
  out.json_path = e.path();
  out.noise_seed = static_cast<uint32_t>(hash64(out.json_path, seed ^ 0x5EEDull));
  out.kind = e["type"].as_name(kEditKindNames);
  const bool metaball = e["type"].as<std::string>() == "metaball";
  std::set<std::string> keys = {"type", "name",  "op",    "blend",  "position",    "rotation",      "scale",
                                "shear", "erode", "detail_type", "density_scale", "coverage", "comment"};
  out.name = e.get<std::string>("name", "");
  if (e.has("op")) out.op = e["op"].as_name(kEditOpNames);
  // A metaball is a sphere that blends by default.
  out.blend = e.has("blend") ? non_negative(e["blend"], 10000.0f) : 0.0f;
  out.transform = parse_transform(e);
  if (e.has("shear")) out.shear.per_metre = e["shear"].as_vec2();
  if (std::abs(out.shear.per_metre.x) > 10.0f || std::abs(out.shear.per_metre.y) > 10.0f)
    e["shear"].fail("shear out of range (|metres per metre| <= 10)");
  if (e.has("erode")) {
    JsonView er = e["erode"];
    check_keys(er, {"amplitude", "frequency", "octaves"});
    out.erosion.amplitude = non_negative(er["amplitude"], 10000.0f);
    out.erosion.frequency = positive(er["frequency"], 10.0f);
    out.erosion.octaves = er.has("octaves") ? static_cast<int>(er["octaves"].as_float_in(1, 8)) : 3;
  }
  out.detail_type = e.has("detail_type") ? e["detail_type"].as_float_in(0.0f, 1.0f) : parent_defaults.detail_type;
  out.density_scale =
      e.has("density_scale") ? e["density_scale"].as_float_in(0.0f, 1.0f) : parent_defaults.density_scale;
  out.coverage = e.has("coverage") ? e["coverage"].as_float_in(0.0f, 1.0f) : parent_defaults.coverage;
  out.profile_depth = parent_defaults.profile_depth;

  switch (out.kind) {
    case EditKind::Sphere:
      keys.insert("radius");
      out.radius = positive(e["radius"]);
      if (metaball && !e.has("blend")) out.blend = out.radius * 0.5f;  // metaball: soft by default
      break;
    case EditKind::Ellipsoid:
      keys.insert("radii");
      out.radii = positive3(e["radii"]);
      break;
    case EditKind::Box:
      keys.insert({"size", "rounding"});
      out.half_extents = positive3(e["size"]) * 0.5f;
      out.rounding = e.has("rounding") ? non_negative(e["rounding"]) : 0.0f;
      if (out.rounding > std::min(out.half_extents.x, std::min(out.half_extents.y, out.half_extents.z)))
        e["rounding"].fail("rounding is larger than half the smallest side");
      break;
    case EditKind::Capsule:
      keys.insert({"a", "b", "radius"});
      out.a = coord3(e["a"]);
      out.b = coord3(e["b"]);
      out.radius = positive(e["radius"]);
      break;
    case EditKind::Particles: {
      keys.insert({"points", "generate", "particle_blend"});
      out.particle_blend = e.has("particle_blend") ? non_negative(e["particle_blend"]) : 0.0f;
      if (e.has("points") == e.has("generate")) e.fail("particles need exactly one of \"points\" or \"generate\"");
      if (e.has("points")) {
        for (const JsonView& p : e["points"].elements()) {
          glm::vec4 v = p.as_vec4();
          if (!(v.w >= kMinSize && v.w <= kMaxCoord))
            p.at(3).fail(strf("particle radius %g is outside %g..%g m", v.w, kMinSize, kMaxCoord));
          for (int i = 0; i < 3; ++i)
            if (std::abs(v[i]) > kMaxCoord) p.at(i).fail("coordinate out of range");
          out.particles.push_back({glm::vec3(v), v.w});
        }
        if (out.particles.empty()) e["points"].fail("expected at least one point [x, y, z, radius]");
      } else {
        out.particles = generate_particles(e["generate"], hash64(out.json_path, seed));
      }
      ctx.particle_count += out.particles.size();
      if (ctx.particle_count > kMaxParticles) e.fail(strf("more than %zu particles in the recipe", kMaxParticles));
      break;
    }
    case EditKind::Mesh: {
      keys.insert({"file", "resolution"});
      if (!ctx.allow_files) e["file"].fail("file edits are not allowed here");
      std::filesystem::path file = ctx.base_dir / e["file"].as<std::string>();
      float res = e.has("resolution") ? positive(e["resolution"], 1000.0f) : 0.0f;
      out.source = file.string();
      try {
        out.grid = voxelize_gltf_file(file, res);
      } catch (const Error& err) {
        e["file"].fail(err.what());
      }
      break;
    }
    case EditKind::Volume: {
      keys.insert({"file", "iso"});
      if (!ctx.allow_files) e["file"].fail("file edits are not allowed here");
      std::filesystem::path file = ctx.base_dir / e["file"].as<std::string>();
      float iso = e.has("iso") ? e["iso"].as_float_in(0.0f, 1.0f) : 0.05f;
      out.source = file.string();
      try {
        out.grid = load_volume_sdf(file, iso);
      } catch (const Error& err) {
        e["file"].fail(err.what());
      }
      break;
    }
    case EditKind::Grown: {
      keys.insert({"spec", "attributes"});
      if (!ctx.allow_files) e["spec"].fail("file edits are not allowed here");
      const std::filesystem::path file = ctx.base_dir / e["spec"].as<std::string>();
      out.grown_simulated = !ctx.grown_constant;
      if (e.has("attributes")) out.grown_simulated = e["attributes"].as_enum({"simulated", "constant"}) == 0 && !ctx.grown_constant;
      out.source = file.string();
      try {
        out.grown = grown_modeling_for(file, ctx.grow_progress, &out.grown_key);
      } catch (const Error& err) {
        e["spec"].fail(err.what());
      }
      break;
    }
    case EditKind::Group: {
      keys.insert("edits");
      for (const JsonView& c : e["edits"].elements()) out.children.push_back(parse_edit(c, ctx, out, seed, depth + 1));
      if (out.children.empty()) e["edits"].fail("a group needs at least one edit");
      break;
    }
  }
  check_keys(e, keys);
  return out;
}

// Shape box in local space, before margins.
Aabb shape_bounds(const Edit& e) {
  Aabb b;
  switch (e.kind) {
    case EditKind::Sphere: b = {glm::vec3(-e.radius), glm::vec3(e.radius)}; break;
    case EditKind::Ellipsoid: b = {-e.radii, e.radii}; break;
    case EditKind::Box: b = {-e.half_extents, e.half_extents}; break;
    case EditKind::Capsule:
      b.add(e.a), b.add(e.b);
      b = b.expanded(e.radius);
      break;
    case EditKind::Particles:
      for (const Particle& p : e.particles) b.add(Aabb{p.center - p.radius, p.center + p.radius});
      b = b.expanded(e.particle_blend);
      break;
    case EditKind::Mesh:
    case EditKind::Volume: b = grid_bounds(*e.grid); break;
    case EditKind::Grown: b = {e.grown->bounds_min, e.grown->bounds_max}; break;
    case EditKind::Group:
      for (const Edit& c : e.children)
        if (c.op != EditOp::Subtract) b.add(c.parent_bounds);
      break;
  }
  return b;
}

void finalize(Edit& e, float band) {
  // Children live in this edit's local space, where a world metre is 1 / scale units.
  float child_band = band / e.transform.min_scale();
  for (Edit& c : e.children) finalize(c, child_band);
  e.local_bounds = shape_bounds(e);
  if (e.kind == EditKind::Particles) e.bins = build_particle_bins(e.particles, e.particle_blend);
  Aabb pb;
  if (!e.local_bounds.empty()) {
    for (int i = 0; i < 8; ++i) {
      glm::vec3 c{(i & 1) ? e.local_bounds.max.x : e.local_bounds.min.x,
                  (i & 2) ? e.local_bounds.max.y : e.local_bounds.min.y,
                  (i & 4) ? e.local_bounds.max.z : e.local_bounds.min.z};
      pb.add(e.transform.to_parent(c));
    }
    if (e.shear.enabled()) {
      // Shear offsets a point at height y by per_metre * (y - position.y): the box grows by the
      // largest offset over its height range.
      float dy = std::max(std::abs(pb.max.y - e.transform.position.y), std::abs(pb.min.y - e.transform.position.y));
      pb.min.x -= std::abs(e.shear.per_metre.x) * dy, pb.max.x += std::abs(e.shear.per_metre.x) * dy;
      pb.min.z -= std::abs(e.shear.per_metre.y) * dy, pb.max.z += std::abs(e.shear.per_metre.y) * dy;
    }
    pb = pb.expanded(e.blend + band);  // erosion only shrinks a shape: no margin needed for it
  }
  e.parent_bounds = pb;
}

Recipe parse_root(const JsonView& root, const std::filesystem::path& base_dir, const RecipeOptions& opt) {
  Recipe r;
  r.file = root.file();
  if (!root.is_object()) root.fail("expected a recipe object");
  check_keys(root, {"name", "seed", "voxel_size", "bounds", "defaults", "profile", "edits", "slices", "comment",
                    "$schema"});
  r.name = root.get<std::string>("name", "cloudscape");
  r.seed = opt.seed ? *opt.seed : root.get<uint64_t>("seed", 1);
  if (root.has("voxel_size")) r.voxel_size = root["voxel_size"].as_float_in(0.25f, 1024.0f);
  if (root.has("bounds")) {
    JsonView b = root["bounds"];
    check_keys(b, {"min", "max"});
    r.bounds_min = coord3(b["min"]);
    r.bounds_max = coord3(b["max"]);
    for (int i = 0; i < 3; ++i)
      if (!(r.bounds_max[i] > r.bounds_min[i])) b["max"].at(i).fail("bounds max must be larger than min");
  }
  if (root.has("defaults")) {
    JsonView d = root["defaults"];
    check_keys(d, {"detail_type", "density_scale", "coverage"});
    if (d.has("detail_type")) r.default_detail_type = d["detail_type"].as_float_in(0.0f, 1.0f);
    if (d.has("density_scale")) r.default_density_scale = d["density_scale"].as_float_in(0.0f, 1.0f);
    if (d.has("coverage")) r.default_coverage = d["coverage"].as_float_in(0.0f, 1.0f);
  }
  if (root.has("profile")) {
    JsonView p = root["profile"];
    check_keys(p, {"depth", "exponent"});
    if (p.has("depth")) r.profile.depth = positive(p["depth"], 4096.0f);
    if (p.has("exponent")) r.profile.exponent = p["exponent"].as_float_in(0.05f, 20.0f);
  }
  if (root.has("slices")) {
    JsonView s = root["slices"];
    check_keys(s, {"heights", "vertical"});
    if (s.has("heights"))
      for (const JsonView& h : s["heights"].elements()) r.slices.heights.push_back(h.as_float_in(-kMaxCoord, kMaxCoord));
    if (s.has("vertical"))
      for (const JsonView& v : s["vertical"].elements()) {
        check_keys(v, {"name", "axis", "at", "range"});
        VerticalSlice vs;
        vs.name = v.get<std::string>("name", "vertical");
        vs.axis = v["axis"].as_enum({"x", "z"}) == 0 ? 0 : 2;
        vs.at = v["at"].as_float_in(-kMaxCoord, kMaxCoord);
        if (v.has("range")) {
          glm::vec2 rg = v["range"].as_vec2();
          if (!(rg.x < rg.y)) v["range"].fail("expected [from, to] with from < to");
          vs.from = rg.x, vs.to = rg.y;
        }
        r.slices.vertical.push_back(vs);
      }
  }
  Ctx ctx{base_dir, opt.allow_files, opt.grown_constant, opt.grow_progress};
  const Edit defaults = recipe_defaults(r);
  for (const JsonView& e : root["edits"].elements()) r.edits.push_back(parse_edit(e, ctx, defaults, r.seed, 0));
  finalize_edits(r, 3.0f * r.voxel_size);
  return r;
}

}  // namespace

Edit recipe_defaults(const Recipe& recipe) {
  Edit d;
  d.detail_type = recipe.default_detail_type;
  d.density_scale = recipe.default_density_scale;
  d.profile_depth = recipe.profile.depth;
  d.coverage = recipe.default_coverage;
  return d;
}

void finalize_edits(Recipe& recipe, float band) {
  for (Edit& e : recipe.edits) finalize(e, band);
}

Recipe load_recipe(const std::filesystem::path& path, const RecipeOptions& options) {
  JsonDocument doc = load_json_file(path);
  return parse_root(doc.view(), path.parent_path(), options);
}

Recipe parse_recipe_text(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                         const RecipeOptions& options) {
  JsonDocument doc = parse_json_text(text, name);
  return parse_root(doc.view(), base_dir, options);
}

}  // namespace cumulo::clouds::bake
