// OpenVDB export of a grown cloud (built only with OpenVDB): a fog volume a DCC tool opens as is.
#include <openvdb/openvdb.h>

#include "engine/core/error.h"
#include "modules/clouds/bake/grow/grown_cloud.h"

namespace cumulo::clouds::grow {

bool write_grown_vdb(const std::filesystem::path& path, const GrownCloud& g) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  // Voxel centres at origin + index * cell: the same world (game metre) positions as grown.nvdf.
  openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(g.cell);
  xf->postTranslate(openvdb::Vec3d(g.origin.x, g.origin.y, g.origin.z));
  grid->setTransform(xf);
  openvdb::FloatGrid::Accessor acc = grid->getAccessor();
  const float scale = 1.0f / (4.0f * g.iso);
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) {
        const float d = std::min(1.0f, g.cloud_water[g.index(i, j, k)] * scale);
        if (d > 1e-3f) acc.setValue(openvdb::Coord(int(i), int(j), int(k)), d);
      }
  grid->insertMeta("cumulo_units", openvdb::StringMetadata("game metres; density = cloud water / (4 iso)"));
  try {
    openvdb::io::File file(path.string());
    file.write({grid});
    file.close();
  } catch (const std::exception& e) {
    fail("%s: cannot write the OpenVDB file: %s", path.string().c_str(), e.what());
  }
  return true;
}

}  // namespace cumulo::clouds::grow
