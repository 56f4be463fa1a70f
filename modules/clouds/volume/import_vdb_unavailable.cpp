// Stand-in for import_vdb.cpp when the build found no OpenVDB (see CMakeLists.txt).
#include "engine/core/error.h"
#include "modules/clouds/volume/import.h"

namespace cumulo::clouds {

CloudscapeVolumes import_vdb(const std::filesystem::path& path, const VdbImportOptions&) {
  fail("%s: this build has no OpenVDB support (install libopenvdb-dev, libtbb-dev, libboost-dev and reconfigure)",
       path.string().c_str());
}

}  // namespace cumulo::clouds
