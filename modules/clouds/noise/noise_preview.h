#pragma once
// PNG previews of the noise textures, for people: slice z = 0 of level 0, one grey tile per channel
// side by side, each repeated 2x2 so a seam would show as a line through the middle.
#include <cstdint>
#include <vector>

#include "modules/clouds/noise/noise_textures.h"

namespace cumulo::clouds {

// The PNG bytes; `cumulo noise` writes them with its other outputs as one FileSet.
std::vector<uint8_t> encode_noise_preview(const NoiseTexture& tex);

}  // namespace cumulo::clouds
