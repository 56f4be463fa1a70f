#pragma once
// Linear HDR images as OpenEXR (libopenexr-dev): 32-bit float R, G, B, A channels, ZIP compressed, written
// atomically (a temporary file renamed over the target, so a failed write leaves the old file).
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

namespace cumulo::clouds {

// Throws cumulo::Error naming the path when the file cannot be written.
void write_exr(const std::filesystem::path& path, uint32_t width, uint32_t height, const std::vector<glm::vec4>& rgba);
// Throws cumulo::Error naming the path for a missing or malformed file (or one without R, G, B).
std::vector<glm::vec4> read_exr(const std::filesystem::path& path, uint32_t* width, uint32_t* height);

}  // namespace cumulo::clouds
