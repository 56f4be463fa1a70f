#include "modules/clouds/bake/compose.h"

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/parallel.h"
#include "engine/core/progress.h"
#include "modules/clouds/bake/grid_sdf.h"
#include "modules/clouds/bake/grow/grown_attributes.h"
#include "modules/clouds/bake/sdf_primitives.h"
#include "modules/clouds/noise/noise.h"

namespace cumulo::clouds::bake {

namespace {

uint64_t cell_key(glm::ivec3 c) {
  return (uint64_t(uint32_t(c.x) & 0x1FFFFF) << 42) | (uint64_t(uint32_t(c.y) & 0x1FFFFF) << 21) |
         uint64_t(uint32_t(c.z) & 0x1FFFFF);
}

// The bin of a point. The quotient is clamped before it becomes an int: a point far from tiny
// particles gives one beyond int's range (undefined behaviour, found by recipe_fuzz). Clamped bins
// only ever hold particles too far away to matter, and keys wrap at 2^21 anyway.
glm::ivec3 cell_of(glm::vec3 p, float cell) {
  const glm::vec3 q = glm::clamp(glm::floor(p / cell), glm::vec3(-1.0e9f), glm::vec3(1.0e9f));
  return glm::ivec3(glm::isnan(q.x) ? 0.0f : q.x, glm::isnan(q.y) ? 0.0f : q.y, glm::isnan(q.z) ? 0.0f : q.z);
}

float particles_distance(const Edit& e, glm::vec3 q) {
  const ParticleBins& bins = *e.bins;
  glm::ivec3 c = cell_of(q, bins.cell);
  float d = kFarDistance;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        auto it = bins.cells.find(cell_key(c + glm::ivec3(dx, dy, dz)));
        if (it == bins.cells.end()) continue;
        for (uint32_t i : it->second) {
          float w;
          d = smooth_union(d, sd_sphere(q - e.particles[i].center, e.particles[i].radius), e.particle_blend, &w);
        }
      }
  return d;
}

void combine(EvalSample& acc, const Edit& e, const EvalSample& v) {
  float w = 0.0f;
  switch (e.op) {
    case EditOp::Union: acc.d = smooth_union(acc.d, v.d, e.blend, &w); break;
    case EditOp::Subtract: acc.d = smooth_subtract(acc.d, v.d, e.blend); return;  // cutouts carry no attributes
    case EditOp::Intersect: acc.d = smooth_intersect(acc.d, v.d, e.blend, &w); break;
  }
  acc.detail_type += (v.detail_type - acc.detail_type) * w;
  acc.density_scale += (v.density_scale - acc.density_scale) * w;
  acc.profile_depth += (v.profile_depth - acc.profile_depth) * w;
  acc.coverage += (v.coverage - acc.coverage) * w;
}

// An edit outside its box: unions and cutouts change nothing; an intersection empties the point.
void combine_culled(EvalSample& acc, const Edit& e) {
  if (e.op == EditOp::Intersect) acc.d = std::max(acc.d, kFarDistance);
}

EvalSample evaluate_edit(const Edit& e, glm::vec3 p_parent, glm::vec3 p_world);

// What a point takes where no edit of a list reaches it: the attributes of the group (or the recipe) around it.
EvalSample outside_sample(const Edit& defaults) {
  EvalSample s;
  s.detail_type = defaults.detail_type;
  s.density_scale = defaults.density_scale;
  s.profile_depth = defaults.profile_depth;
  s.coverage = defaults.coverage;
  return s;
}

EvalSample evaluate_list(const std::vector<Edit>& edits, glm::vec3 p, glm::vec3 p_world, const Edit* defaults) {
  EvalSample acc = defaults ? outside_sample(*defaults) : EvalSample{};
  for (const Edit& e : edits) {
    if (e.parent_bounds.contains(p))
      combine(acc, e, evaluate_edit(e, p, p_world));
    else
      combine_culled(acc, e);
  }
  return acc;
}

EvalSample evaluate_edit(const Edit& e, glm::vec3 p_parent, glm::vec3 p_world) {
  glm::vec3 p = p_parent;
  if (e.shear.enabled()) {
    float h = p.y - e.transform.position.y;
    p.x -= e.shear.per_metre.x * h;
    p.z -= e.shear.per_metre.y * h;
  }
  glm::vec3 q = e.transform.to_local(p);
  EvalSample s;
  s.detail_type = e.detail_type;
  s.density_scale = e.density_scale;
  s.profile_depth = e.profile_depth;
  s.coverage = e.coverage;
  switch (e.kind) {
    case EditKind::Sphere: s.d = sd_sphere(q, e.radius); break;
    case EditKind::Ellipsoid: s.d = sd_ellipsoid(q, e.radii); break;
    case EditKind::Box: s.d = sd_round_box(q, e.half_extents, e.rounding); break;
    case EditKind::Capsule: s.d = sd_capsule(q, e.a, e.b, e.radius); break;
    case EditKind::Particles: s.d = particles_distance(e, q); break;
    case EditKind::Mesh:
    case EditKind::Volume: s.d = e.grid->sample(q); break;
    case EditKind::Group: s = evaluate_list(e.children, q, p_world, &e); break;
    case EditKind::Grown:
      s.d = e.grown->signed_distance(q);
      if (e.grown_simulated) {
        s.detail_type = e.grown->detail_type.sample(q);
        s.density_scale = e.grown->density_scale.sample(q);
        s.profile_depth = e.grown->profile_depth.sample(q) * e.transform.min_scale();
      }
      break;
  }
  if (s.d < kFarDistance) s.d *= e.transform.min_scale();
  if (e.erosion.enabled() && s.d < kFarDistance)
    s.d += e.erosion.amplitude * erosion_noise(p_world, e.erosion.frequency, e.erosion.octaves, e.noise_seed);
  return s;
}

}  // namespace

float erosion_noise(glm::vec3 p, float frequency, int octaves, uint32_t seed) {
  // The noise module's improved-Perlin fBm (roughly -1..1); its lattice period of 4096 cells never
  // repeats inside a cloudscape (a 4 km box at 0.01 cycles per metre spans 41 cells).
  float n = perlin_fbm(p * frequency, 4096, octaves, seed);
  return std::clamp(0.5f + 0.7f * n, 0.0f, 1.0f);
}

std::shared_ptr<const ParticleBins> build_particle_bins(const std::vector<Particle>& particles, float blend) {
  auto bins = std::make_shared<ParticleBins>();
  float rmax = 0.0f;
  for (const Particle& p : particles) rmax = std::max(rmax, p.radius);
  bins->cell = 2.0f * rmax + blend;
  for (uint32_t i = 0; i < particles.size(); ++i)
    bins->cells[cell_key(cell_of(particles[i].center, bins->cell))].push_back(i);
  return bins;
}

BakeGrid make_grid(const Recipe& recipe, glm::uvec3 dims_override) {
  BakeGrid g;
  glm::vec3 ext = recipe.bounds_max - recipe.bounds_min;
  for (int a = 0; a < 3; ++a) {
    uint32_t n = dims_override[a] ? dims_override[a]
                                  : static_cast<uint32_t>(std::max(1.0f, std::round(ext[a] / recipe.voxel_size)));
    if (n > 4096) fail("%s: the bake grid would have %u voxels along axis %d (at most 4096)", recipe.file.c_str(), n, a);
    g.dims[a] = n;
    g.spacing[a] = ext[a] / static_cast<float>(n);
  }
  g.origin = recipe.bounds_min + 0.5f * g.spacing;
  return g;
}

EvalSample evaluate_point(const Recipe& recipe, glm::vec3 p) {
  const Edit defaults = recipe_defaults(recipe);
  return evaluate_list(recipe.edits, p, p, &defaults);
}

Composed compose(const Recipe& recipe, const BakeGrid& grid, Progress* progress) {
  Composed out;
  const size_t n = grid.count();
  out.sdf.assign(n, kFarDistance);
  out.detail_type.assign(n, recipe.default_detail_type);
  out.density_scale.assign(n, recipe.default_density_scale);
  out.coverage.assign(n, recipe.default_coverage);
  out.profile_depth.assign(n, recipe.profile.depth);
  const size_t rows = size_t(grid.dims.y) * grid.dims.z;
  std::vector<uint64_t> evals(rows, 0);
  const EvalSample outside = outside_sample(recipe_defaults(recipe));

  parallel_for(
      rows,
      [&](size_t rb, size_t re) {
        struct Active {
          const Edit* edit;
          int x0, x1;
        };
        std::vector<Active> active;
        for (size_t row = rb; row < re; ++row) {
          uint32_t y = static_cast<uint32_t>(row % grid.dims.y), z = static_cast<uint32_t>(row / grid.dims.y);
          glm::vec3 p0 = grid.position(0, y, z);
          active.clear();
          bool any_intersect = false;
          for (const Edit& e : recipe.edits) {
            const Aabb& b = e.parent_bounds;
            bool crosses = !b.empty() && p0.y >= b.min.y && p0.y <= b.max.y && p0.z >= b.min.z && p0.z <= b.max.z;
            int x0 = 0, x1 = -1;
            if (crosses) {
              x0 = std::max(0, static_cast<int>(std::ceil((b.min.x - p0.x) / grid.spacing.x)));
              x1 = std::min(static_cast<int>(grid.dims.x) - 1, static_cast<int>(std::floor((b.max.x - p0.x) / grid.spacing.x)));
            }
            if (x0 <= x1 || e.op == EditOp::Intersect) active.push_back({&e, x0, x1});
            any_intersect |= e.op == EditOp::Intersect;
          }
          if (active.empty()) {
            if (progress) progress->add(1.0);
            continue;
          }
          uint64_t count = 0;
          for (uint32_t x = 0; x < grid.dims.x; ++x) {
            glm::vec3 p = grid.position(x, y, z);
            EvalSample acc = outside;
            bool touched = false;
            for (const Active& a : active) {
              if (static_cast<int>(x) >= a.x0 && static_cast<int>(x) <= a.x1) {
                combine(acc, *a.edit, evaluate_edit(*a.edit, p, p));
                touched = true;
                ++count;
              } else {
                combine_culled(acc, *a.edit);
              }
            }
            if (!touched && !any_intersect) continue;
            size_t i = grid.index(x, y, z);
            out.sdf[i] = acc.d;
            out.detail_type[i] = acc.detail_type;
            out.density_scale[i] = acc.density_scale;
            out.coverage[i] = acc.coverage;
            out.profile_depth[i] = acc.profile_depth;
          }
          evals[row] = count;
          if (progress) progress->add(1.0);
        }
      },
      4);
  for (uint64_t c : evals) out.edit_evaluations += c;
  return out;
}

}  // namespace cumulo::clouds::bake
