#pragma once
// PNG previews of the noise textures, for people: slice z = 0 of level 0, one grey tile per channel
// side by side, each repeated 2x2 so a seam would show as a line through the middle.
#include <filesystem>

#include "modules/clouds/noise/noise_textures.h"

namespace cumulo::clouds {

// Throws cumulo::Error naming the path when the PNG cannot be written.
void write_noise_preview(const std::filesystem::path& path, const NoiseTexture& tex);

}  // namespace cumulo::clouds
