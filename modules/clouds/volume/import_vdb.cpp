// OpenVDB import. The only file of the module that includes OpenVDB (its headers compile slowly
// and pull in Boost and TBB), so nothing else depends on them.
#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/core/memory_budget.h"
#include "engine/core/message.h"
#include "engine/core/number.h"
#include "engine/core/parallel.h"
#include "modules/clouds/volume/distance.h"
#include "modules/clouds/volume/import.h"

namespace cumulo::clouds {

namespace {

// ---- truncation and size checks before OpenVDB reads anything -----------------------------------
// OpenVDB trusts the stream: a file cut short imports with garbage values past the cut (the active
// voxel count lives in the intact part), and lengths read from a cut header size allocations (one
// 300-byte cut made it allocate 18 GB). So the container is walked first with every length and
// position checked against the file's size: the header (io::Archive::readHeader), the file metadata
// (MetaMap::readMeta: name, type name, byte count and bytes per item) and the grid descriptors
// (io::GridDescriptor::read: names, type, then the grid, block and end positions; grids follow each
// other, each descriptor at the previous grid's end). OpenVDB then reads only files whose every grid
// ends inside the file, and its reads are bounded by what the file holds.
class VdbScan {
 public:
  VdbScan(const std::string& path, const char* name) : in_(path, std::ios::binary), n_(name) {
    if (!in_) fail("%s: cannot read VDB file: cannot open: %s", n_, std::strerror(errno));
    in_.seekg(0, std::ios::end);
    size_ = uint64_t(in_.tellg());
    in_.seekg(0);
  }

  // The end position of every grid the descriptors list, by grid name.
  std::map<std::string, uint64_t> grids() {
    if (u64("magic") != uint64_t(uint32_t(openvdb::OPENVDB_MAGIC))) fail("%s: cannot read VDB file: not an OpenVDB file (bad magic)", n_);
    const uint32_t version = u32("file version");
    if (version < openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP || version > 1000)
      fail("%s: cannot read VDB file: unsupported OpenVDB file version %u", n_, version);
    skip(8, "library version");  // major, minor
    const bool offsets = bytes(1, "grid offsets flag")[0] != 0;
    if (version >= openvdb::OPENVDB_FILE_VERSION_SELECTIVE_COMPRESSION &&
        version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION)
      skip(1, "compression flag");
    skip(version >= openvdb::OPENVDB_FILE_VERSION_BOOST_UUID ? 36 : 16, "uuid");
    if (!offsets) fail("%s: the file has no grid offsets (written as a stream): re-save it with openvdb::io::File", n_);
    const uint32_t meta = u32("file metadata count");
    for (uint32_t i = 0; i < meta; ++i) {
      skip(u32("file metadata name"), "file metadata name");
      skip(u32("file metadata type"), "file metadata type");
      skip(u32("file metadata size"), "file metadata value");
    }
    const uint32_t count = u32("grid count");
    std::map<std::string, uint64_t> out;
    for (uint32_t i = 0; i < count; ++i) {
      const std::string unique = text("grid name");
      skip(u32("grid type"), "grid type");
      if (version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) skip(u32("grid instance parent"), "grid instance parent");
      const uint64_t at = pos_;
      const uint64_t grid = u64("grid position"), block = u64("block position"), end = u64("end position");
      const std::string name = openvdb::io::GridDescriptor::stripSuffix(unique);
      if (grid < at || block < grid || end < block)
        fail("%s: grid '%s': corrupt positions (grid %llu, data %llu, end %llu)", n_, clip(name, 64).c_str(),
             (unsigned long long)grid, (unsigned long long)block, (unsigned long long)end);
      if (end > size_)
        fail("%s: truncated: grid '%s' ends at byte %llu, the file has %llu bytes", n_, clip(name, 64).c_str(),
             (unsigned long long)end, (unsigned long long)size_);
      out.emplace(name, end);
      seek(end);  // the next descriptor follows this grid
    }
    return out;
  }
  uint64_t size() const { return size_; }

 private:
  void check(uint64_t n, const char* what) const {
    if (n > size_ - pos_)
      fail("%s: truncated: %s at byte %llu needs %llu bytes, the file has %llu", n_, what, (unsigned long long)pos_,
           (unsigned long long)n, (unsigned long long)size_);
  }
  void seek(uint64_t to) {
    pos_ = to;
    in_.seekg(std::streamoff(to));
  }
  void skip(uint64_t n, const char* what) {
    check(n, what);
    seek(pos_ + n);
  }
  std::string bytes(uint64_t n, const char* what) {
    check(n, what);  // so the allocation below is bounded by the file
    std::string b(size_t(n), '\0');
    in_.read(b.data(), std::streamsize(n));
    if (!in_) fail("%s: read error in %s", n_, what);
    pos_ += n;
    return b;
  }
  std::string text(const char* what) { return bytes(u32(what), what); }
  uint32_t u32(const char* what) {
    uint32_t v;
    std::memcpy(&v, bytes(4, what).data(), 4);
    return v;
  }
  uint64_t u64(const char* what) {
    uint64_t v;
    std::memcpy(&v, bytes(8, what).data(), 8);
    return v;
  }

  std::ifstream in_;
  const char* n_;
  uint64_t size_ = 0, pos_ = 0;
};

openvdb::FloatGrid::Ptr read_float_grid(const std::string& file_name, const std::string& wanted) {
  const char* n = file_name.c_str();
  VdbScan(file_name, n).grids();  // throws for a truncated or inconsistent container
  // Past the container, counts inside a grid (tiles, children, metadata sizes) still come from the
  // file, and io::File's own stream fails silently at its end: a count of 4e9 children then loops
  // (and allocates a 270 KB node) 4e9 times on failed reads. So OpenVDB reads the file through our
  // stream, which throws at the first short read: its work is bounded by the bytes the file holds.
  std::ifstream in(file_name, std::ios::binary);
  if (!in) fail("%s: cannot read VDB file: cannot open: %s", n, std::strerror(errno));
  in.exceptions(std::ios::failbit | std::ios::badbit);
  openvdb::io::Stream stream(in, /*delayLoad=*/false);
  openvdb::GridPtrVecPtr grids = stream.getGrids();
  if (!grids) fail("%s: cannot read VDB file: no grids", n);
  std::string listing, chosen;
  openvdb::GridBase::Ptr found;
  for (const auto& g : *grids) {
    listing += strf("%s'%s' (%s)", listing.empty() ? "" : ", ", g->getName().c_str(), g->valueType().c_str());
    const bool is_float = g->valueType() == openvdb::typeNameAsString<float>();
    if (!wanted.empty() && g->getName() == wanted) {
      if (!is_float) fail("%s: grid '%s' holds %s values, not float", n, wanted.c_str(), g->valueType().c_str());
      chosen = wanted;
      found = g;
    } else if (wanted.empty() && chosen.empty() && is_float) {
      chosen = g->getName();
      found = g;
    }
  }
  if (chosen.empty() && !wanted.empty())
    fail("%s: no grid named '%s' (grids: %s)", n, wanted.c_str(), listing.empty() ? "none" : listing.c_str());
  if (chosen.empty()) fail("%s: no float grid (grids: %s)", n, listing.empty() ? "none" : listing.c_str());
  openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(found);
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
  } catch (const Error&) {
    throw;
  } catch (const std::ios_base::failure&) {
    fail("%s: truncated or corrupt: a grid's data ends before what it describes", n);
  } catch (const std::bad_alloc&) {
    // The scan bounds every length by the file size; what remains is a grid larger than memory.
    fail("%s: out of memory reading the VDB grid (%llu-byte file)", n,
         static_cast<unsigned long long>(std::filesystem::file_size(path)));
  } catch (const std::exception& e) {  // openvdb::Exception and what its readers let through
    fail("%s: cannot read VDB file: %s", n, library_message(e.what()).c_str());
  }
  const bool level_set = grid->getGridClass() == openvdb::GRID_LEVEL_SET;
  // The transform is read from the file: its voxel size is an outside number like any other.
  const double vdb_voxel_d = grid->voxelSize()[0];
  if (number_problem<float>(vdb_voxel_d) || !(vdb_voxel_d > 0.0))
    fail("%s: grid '%s': voxel size %g is not a positive 32-bit float", n, grid->getName().c_str(), vdb_voxel_d);
  const float vdb_voxel = float(vdb_voxel_d);

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
  // Peak bytes per voxel of the resampled grid: samples, SDF and its refined copy (12), masks (2),
  // EDT scratch (8), then the four outputs with their float and serialized copies (about 34).
  constexpr uint64_t kImportBytesPerVoxel = 56;
  check_memory_budget(saturating_product({size.x, size.y, size.z, kImportBytesPerVoxel}),
                      strf("%s: importing as %ux%ux%u voxels of %g m (--voxel-size, --bounds, --max-size)", n, size.x,
                           size.y, size.z, voxel));
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

  // Voxel values are outside numbers like the header's: a NaN or infinite density or distance (a
  // corrupt uncompressed leaf reads as NaN) would otherwise import as silent garbage.
  for (size_t i = 0; i < count; ++i)
    if (!std::isfinite(samples[i])) {
      const size_t x = i % size.x, y = (i / size.x) % size.y, z = i / (size_t(size.x) * size.y);
      const glm::vec3 p = bmin + (glm::vec3(x, y, z) + 0.5f) * voxel;
      fail("%s: grid '%s' holds a value that is not a finite number (%g) near world (%g, %g, %g)", n,
           grid->getName().c_str(), double(samples[i]), p.x, p.y, p.z);
    }
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
