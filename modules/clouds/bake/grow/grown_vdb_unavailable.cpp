// Builds without OpenVDB: grown clouds are written as .nvdf only.
#include "modules/clouds/bake/grow/grown_cloud.h"

namespace cumulo::clouds::grow {

bool write_grown_vdb(const std::filesystem::path&, const GrownCloud&) { return false; }

}  // namespace cumulo::clouds::grow
