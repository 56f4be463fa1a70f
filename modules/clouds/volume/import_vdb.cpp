// OpenVDB import. The only file of the module that includes OpenVDB (its headers compile slowly
// and pull in Boost and TBB), so nothing else depends on them.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/core/parallel.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/import.h"

namespace cumulo::clouds {

namespace {

openvdb::FloatGrid::Ptr read_float_grid(const std::string& file_name, const std::string& wanted) {
  const char* n = file_name.c_str();
  openvdb::io::File file(file_name);
  file.open(false);  // no delayed loading: we read the whole grid now
  openvdb::GridPtrVecPtr grids = file.readAllGridMetadata();
  std::string listing, chosen;
  for (const auto& g : *grids) {
    listing += strf("%s'%s' (%s)", listing.empty() ? "" : ", ", g->getName().c_str(), g->valueType().c_str());
    const bool is_float = g->valueType() == openvdb::typeNameAsString<float>();
    if (!wanted.empty() && g->getName() == wanted) {
      if (!is_float) fail("%s: grid '%s' holds %s values, not float", n, wanted.c_str(), g->valueType().c_str());
      chosen = wanted;
    } else if (wanted.empty() && chosen.empty() && is_float) {
      chosen = g->getName();
    }
  }
  if (chosen.empty() && !wanted.empty())
    fail("%s: no grid named '%s' (grids: %s)", n, wanted.c_str(), listing.empty() ? "none" : listing.c_str());
  if (chosen.empty()) fail("%s: no float grid (grids: %s)", n, listing.empty() ? "none" : listing.c_str());
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid(chosen));
  file.close();
  if (!grid) fail("%s: grid '%s' could not be read as a float grid", n, chosen.c_str());
  return grid;
}

// World-space box of the grid's active voxels (each voxel a cube around its centre).
std::pair<glm::vec3, glm::vec3> active_world_box(const openvdb::FloatGrid& grid, const char* n) {
  const openvdb::CoordBBox bbox = grid.evalActiveVoxelBoundingBox();
  if (bbox.empty()) fail("%s: grid '%s' has no active voxels", n, grid.getName().c_str());
  const openvdb::Vec3d lo = bbox.min().asVec3d() - 0.5, hi = bbox.max().asVec3d() + 0.5;
  glm::vec3 wmin(INFINITY), wmax(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const openvdb::Vec3d p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    const openvdb::Vec3d w = grid.indexToWorld(p);
    for (int a = 0; a < 3; ++a) {
      wmin[a] = std::min(wmin[a], float(w[a]));
      wmax[a] = std::max(wmax[a], float(w[a]));
    }
  }
  return {wmin, wmax};
}

// The distance transform puts the surface halfway between an inside and an outside voxel centre.
// Next to the surface the density itself says better where the iso-surface lies: to first order
// it is (iso - density) / |grad density| away. Used only on voxels with a 6-neighbour on the other
// side, and only when that estimate agrees in sign and stays within one voxel.
void refine_near_surface(const std::vector<float>& density, const std::vector<uint8_t>& inside, glm::uvec3 s,
                         float voxel, float iso, std::vector<float>& sdf) {
  auto at = [&](int x, int y, int z) {
    x = std::clamp(x, 0, int(s.x) - 1), y = std::clamp(y, 0, int(s.y) - 1), z = std::clamp(z, 0, int(s.z) - 1);
    return (size_t(z) * s.y + size_t(y)) * s.x + size_t(x);
  };
  std::vector<float> refined(sdf);
  parallel_for(s.z, [&](size_t z0, size_t z1) {
    for (int z = int(z0); z < int(z1); ++z)
      for (int y = 0; y < int(s.y); ++y)
        for (int x = 0; x < int(s.x); ++x) {
          const size_t i = at(x, y, z);
          const size_t n[6] = {at(x - 1, y, z), at(x + 1, y, z), at(x, y - 1, z),
                               at(x, y + 1, z), at(x, y, z - 1), at(x, y, z + 1)};
          bool boundary = false;
          for (size_t j : n) boundary |= inside[j] != inside[i];
          if (!boundary) continue;
          const glm::vec3 grad(density[n[1]] - density[n[0]], density[n[3]] - density[n[2]],
                               density[n[5]] - density[n[4]]);  // per 2 voxels (clamped at the edges)
          const float g = glm::length(grad) / (2.0f * voxel);
          if (!(g > 1e-6f)) continue;
          const float d = (iso - density[i]) / g;
          if ((inside[i] ? d <= 0.0f : d > 0.0f) && std::fabs(d) <= voxel) refined[i] = d;
        }
  });
  sdf.swap(refined);
}

}  // namespace

CloudscapeVolumes import_vdb(const std::filesystem::path& path, const VdbImportOptions& o) {
  const std::string file_name = path.string();
  const char* n = file_name.c_str();
  openvdb::initialize();
  openvdb::FloatGrid::Ptr grid;
  try {
    grid = read_float_grid(file_name, o.grid);
  } catch (const openvdb::Exception& e) {
    fail("%s: cannot read VDB file: %s", n, e.what());
  }
  const bool level_set = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
  const float vdb_voxel = float(grid->voxelSize()[0]);

  // Our grid: an axis-aligned box around the active voxels (or the given bounds) at one voxel size.
  glm::vec3 bmin, bmax;
  if (o.bounds) {
    std::tie(bmin, bmax) = *o.bounds;
    for (int a = 0; a < 3; ++a)
      if (!(bmax[a] > bmin[a])) fail("%s: import bounds axis %c: min %g >= max %g", n, "xyz"[a], bmin[a], bmax[a]);
  } else {
    std::tie(bmin, bmax) = active_world_box(*grid, n);
  }
  float voxel = o.voxel_size;
  if (!(voxel > 0.0f)) {
    voxel = vdb_voxel;
    const float longest = std::max({bmax.x - bmin.x, bmax.y - bmin.y, bmax.z - bmin.z});
    if (longest / voxel > float(o.max_dimension)) voxel = longest / float(o.max_dimension);
  }
  if (!o.bounds) {
    const float pad = o.padding_m >= 0.0f ? o.padding_m : 2.0f * voxel;
    bmin -= pad;
    bmax += pad;
  }
  glm::uvec3 size;
  for (int a = 0; a < 3; ++a) {
    const double cells = std::ceil(double(bmax[a] - bmin[a]) / voxel - 1e-4);
    if (!(cells >= 1.0) || cells > 4096.0)
      fail("%s: %g m at %g m voxels makes %g voxels along %c (1..4096); choose another --voxel-size", n,
           bmax[a] - bmin[a], voxel, cells, "xyz"[a]);
    size[a] = uint32_t(cells);
  }
  LOG_INFO("import: %s grid '%s' (voxel %g m) -> %ux%ux%u at %g m", level_set ? "level set" : "density",
           grid->getName().c_str(), vdb_voxel, size.x, size.y, size.z, voxel);

  // Resample at our voxel centres. Density with the box filter averages k^3 trilinear samples
  // spread over the voxel (k = our voxel / VDB voxel, at most 4), so thin features are not lost
  // when downsampling; distances are smooth and sampled once at the centre.
  const uint32_t k = (!level_set && o.filter == VdbFilter::Box)
                         ? std::clamp(uint32_t(std::ceil(voxel / vdb_voxel - 1e-3f)), 1u, 4u)
                         : 1u;
  const size_t count = size_t(size.x) * size.y * size.z;
  std::vector<float> samples(count);
  parallel_for(size.z, [&](size_t z0, size_t z1) {
    openvdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
    openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(
        acc, grid->transform());
    for (uint32_t z = uint32_t(z0); z < z1; ++z)
      for (uint32_t y = 0; y < size.y; ++y)
        for (uint32_t x = 0; x < size.x; ++x) {
          float sum = 0.0f;
          for (uint32_t sz = 0; sz < k; ++sz)
            for (uint32_t sy = 0; sy < k; ++sy)
              for (uint32_t sx = 0; sx < k; ++sx) {
                const glm::vec3 p = bmin + (glm::vec3(x, y, z) + (glm::vec3(sx, sy, sz) + 0.5f) / float(k)) * voxel;
                sum += sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z));
              }
          samples[(size_t(z) * size.y + y) * size.x + x] = sum / float(k * k * k);
        }
  });

  std::vector<uint8_t> inside(count);
  for (size_t i = 0; i < count; ++i) inside[i] = level_set ? samples[i] < 0.0f : samples[i] >= o.iso;
  std::vector<float> sdf = signed_distance_from_mask(inside, size, voxel);
  size_t inside_count = 0;
  for (uint8_t v : inside) inside_count += v;
  if (inside_count == 0) LOG_WARN("%s: no voxel is inside the cloud (density never reaches %g)", n, o.iso);
  if (!level_set) refine_near_surface(samples, inside, size, voxel, o.iso, sdf);
  if (level_set) {
    // Inside the narrow band the level set's own distance (world units) is exact, better than the
    // half-voxel surface placement of the transform; beyond it only the sign is known, and the
    // transform of that sign is the distance (never less than the band's half width).
    // A trilinear sample is exact only if all 8 VDB voxels around it are in the band: within
    // band - sqrt(3) VDB voxels of the surface.
    const float band = grid->background();
    const float exact = band - 1.75f * vdb_voxel;
    for (size_t i = 0; i < count; ++i) {
      if (std::fabs(samples[i]) < exact) sdf[i] = samples[i];
      else sdf[i] = std::copysign(std::max(std::fabs(sdf[i]), band), samples[i]);
    }
  }
  return nvdfs_from_sdf(sdf, size, voxel, bmin, o.derive);
}

}  // namespace cumulo::clouds
