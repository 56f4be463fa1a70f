#pragma once
// Turns what a Cloudscape names into files the renderer loads, doing the offline work once:
// - a folder of .nvdf files (`cumulo bake` or `cumulo import` output) is used as it is, after checking
//   that the files the renderer reads are there;
// - a recipe (.json) is baked on first use into the bake cache (<cache>/bakes/<name>-<key>/, cache dir
//   as for shaders: CUMULO_CACHE_DIR, else ~/.cache/cumulo) with a progress line, and reused while the
//   recipe text, the files it names and the baker are unchanged;
// - the voxel noise (`cumulo noise`'s voxel_noise.nvdf, RGBA8) is generated once into <cache>/noise/.
// Concurrent processes (parallel tests) wait for each other on a lock file instead of baking twice.
// Every error is a cumulo::Error naming the asset and `where` (the level file and JSON path).
#include <cstdint>
#include <filesystem>
#include <string>

#include "engine/ecs/world.h"

namespace cumulo::clouds {

// Bumped whenever the baker's output for the same recipe changes (part of the cache key).
// bake-2: the coverage threshold (modeling.nvdf's alpha, coverage.nvdf). bake-3: field_fair.nvdf; grown attributes with
// the column-height detail type.
inline constexpr const char* kBakeCacheVersion = "bake-3";

std::filesystem::path prepare_cloudscape_asset(const std::filesystem::path& asset, const std::string& where);
std::filesystem::path prepare_voxel_noise(int size = 128, uint64_t seed = 1);
// The 2015 sky noises for the 2.5D sky (sky_noise_base.nvdf, sky_noise_detail.nvdf, curl_noise.nvdf, as
// `cumulo noise` writes them), generated into the cache on first use; returns their folder.
std::filesystem::path prepare_sky_noise(int size = 128, uint64_t seed = 1);
// Every Cloudscape of a loaded level resolved (Cloudscape::resolved; paths relative to `level_dir`);
// throws naming the Cloudscape's place for a bad asset or a Transform without one positive uniform scale.
// Returns whether there is any.
bool resolve_cloudscapes(ecs::World& world, const std::filesystem::path& level_dir);
// The bake-cache folder a recipe would use (for tests and messages).
std::filesystem::path bake_cache_folder(const std::filesystem::path& recipe);

}  // namespace cumulo::clouds
