#include "modules/clouds/scene/cloudscape_assets.h"

#include <cmath>
#include <cstdio>
#include <functional>

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/file_lock.h"
#include "engine/core/hash.h"
#include "engine/core/log.h"
#include "engine/core/progress.h"
#include "engine/gpu/context.h"
#include "engine/scene/components.h"
#include "modules/clouds/scene/cloudscape.h"
#include "modules/clouds/bake/bake.h"
#include "modules/clouds/noise/noise_encode.h"
#include "modules/clouds/noise/noise_textures.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds {
namespace fs = std::filesystem;
namespace {

// The files the renderer reads from a cloudscape folder (both format sets).
constexpr const char* kAssetFiles[] = {"modeling.nvdf", "modeling_bc1.nvdf", "field.nvdf", "field_bc1.nvdf"};
// Read when present: the BC1 path's coverage thresholds (volume/nvdf.h). A folder without it (an import, an
// older bake) has threshold 0 everywhere; every bake writes it, so a bake-cache folder is complete with it.
constexpr const char* kOptionalAssetFiles[] = {"coverage.nvdf"};  // field_fair.nvdf: only when some cloud reaches the band

bool complete_folder(const fs::path& dir) {
  std::error_code ec;
  for (const char* f : kAssetFiles)
    if (!fs::is_regular_file(dir / f, ec)) return false;
  return true;
}

uint64_t file_stamp(const fs::path& p, uint64_t h) {
  std::error_code ec;
  auto size = fs::file_size(p, ec);
  auto time = fs::last_write_time(p, ec).time_since_epoch().count();
  h = hash64(p.string(), h);
  h = hash64(&size, sizeof size, h);
  return hash64(&time, sizeof time, h);
}

}  // namespace

fs::path bake_cache_folder(const fs::path& recipe) {
  uint64_t h = hash64(std::string_view(kBakeCacheVersion));
  h = hash64(read_file_text(recipe), h);
  // Mesh and volume edits read other files: their size and time are part of the key.
  bake::Recipe r = bake::load_recipe(recipe);
  // Grown edits are keyed by their spec's content and the solver version; mesh and volume edits by
  // their files' size and time. Groups are walked: an edit inside one counts as much as a top-level one.
  std::function<void(const std::vector<bake::Edit>&)> walk = [&](const std::vector<bake::Edit>& edits) {
    for (const bake::Edit& e : edits) {
      if (e.kind == bake::EditKind::Grown)
        h = hash64(&e.grown_key, sizeof e.grown_key, hash64(std::string_view(e.grown_simulated ? "sim" : "const"), h));
      else if (!e.source.empty())
        h = file_stamp(e.source, h);
      walk(e.children);
    }
  };
  walk(r.edits);
  char key[17];
  std::snprintf(key, sizeof key, "%016llx", static_cast<unsigned long long>(h));
  return gpu::default_cache_dir() / "bakes" / (recipe.stem().string() + "-" + key);
}

fs::path prepare_cloudscape_asset(const fs::path& asset, const std::string& where) {
  std::error_code ec;
  if (fs::is_directory(asset, ec)) {
    // A `cumulo bake` or `cumulo import` killed while it replaced the folder's files: finished or undone first, so the
    // assets read are one bake's, never a mix of two.
    try {
      for (const std::string& line : recover_file_sets(asset)) LOG_INFO("%s", line.c_str());
    } catch (const Error& e) {
      fail("%s: %s", where.c_str(), e.what());
    }
    if (!complete_folder(asset)) {
      std::string missing;
      for (const char* f : kAssetFiles)
        if (!fs::is_regular_file(asset / f, ec)) missing += std::string(missing.empty() ? "" : ", ") + f;
      fail("%s: cloudscape folder %s lacks %s (write it with `cumulo bake` or `cumulo import`)", where.c_str(),
           asset.string().c_str(), missing.c_str());
    }
    return asset;
  }
  if (!fs::is_regular_file(asset, ec)) fail("%s: cloudscape asset not found: %s", where.c_str(), asset.string().c_str());
  if (asset.extension() != ".json")
    fail("%s: %s is neither a recipe (.json) nor a folder of .nvdf files", where.c_str(), asset.string().c_str());
  fs::path dir;
  try {
    dir = bake_cache_folder(asset);
  } catch (const Error& e) {
    fail("%s: %s", where.c_str(), e.what());
  }
  auto baked = [&dir] {
    std::error_code ec;
    for (const char* f : kOptionalAssetFiles)
      if (!fs::is_regular_file(dir / f, ec)) return false;
    return complete_folder(dir);
  };
  if (baked()) return dir;
  fs::create_directories(dir.parent_path());
  FileLock lock(dir.string() + ".lock");
  if (baked()) return dir;  // another process baked it while we waited
  std::printf("cumulo: baking %s into the bake cache %s (first use; later runs reuse it)\n", asset.string().c_str(),
              dir.string().c_str());
  std::fflush(stdout);
  try {
    bake::Recipe recipe = bake::load_recipe(asset);
    bake::BakeResult result = bake::bake_recipe(recipe);
    // Written beside the final name and renamed at the end: a killed bake never leaves a half folder.
    fs::path tmp = dir.string() + ".partial";
    fs::remove_all(tmp, ec);
    bake::write_bake_outputs(recipe, result, tmp);
    fs::remove_all(dir, ec);
    fs::rename(tmp, dir);
  } catch (const Error& e) {
    fail("%s: %s", where.c_str(), e.what());
  }
  return dir;
}

fs::path prepare_voxel_noise(int size, uint64_t seed) {
  fs::path file = gpu::default_cache_dir() / "noise" /
                  ("voxel_noise-" + std::to_string(size) + "-s" + std::to_string(seed) + "-rgba8.nvdf");
  std::error_code ec;
  if (fs::is_regular_file(file, ec)) return file;
  fs::create_directories(file.parent_path());
  FileLock lock(file.string() + ".lock");
  if (fs::is_regular_file(file, ec)) return file;
  std::printf("cumulo: generating the %d^3 voxel noise into %s (first use)\n", size, file.string().c_str());
  std::fflush(stdout);
  VoxelNoiseParams p;
  p.size = size;
  p.seed = seed;
  Progress progress("voxel noise", double(size) * size * size);
  NoiseTexture tex = generate_voxel_noise(p, &progress);
  progress.finish();
  // The channels `cumulo noise` writes into voxel_noise.nvdf.
  save_volume(file, noise_to_volume(tex, VolumeEncoding::RGBA8,
                                    {{"curly_alligator_low"}, {"curly_alligator_high"}, {"alligator_low"}, {"alligator_high"}}));
  return file;
}

fs::path prepare_sky_noise(int size, uint64_t seed) {
  const fs::path dir = gpu::default_cache_dir() / "noise" / ("sky_noise-" + std::to_string(size) + "-s" + std::to_string(seed));
  std::error_code ec;
  auto complete = [&] { return fs::is_regular_file(dir / "curl_noise.nvdf", ec); };  // written last
  if (complete()) return dir;
  fs::create_directories(dir);
  FileLock lock(dir.string() + ".lock");
  if (complete()) return dir;
  std::printf("cumulo: generating the 2.5D sky's noises (%d^3 Perlin-Worley + Worley, %d^3 Worley, %d^2 curl) into %s (first use)\n",
              size, std::max(4, size / 4), size, dir.string().c_str());
  std::fflush(stdout);
  SkyNoiseParams p;
  p.seed = seed;
  p.base_size = size;
  p.detail_size = std::max(4, size / 4);
  p.curl_size = size;
  Progress progress("sky noise", double(size) * size * size);
  const NoiseTexture base = generate_sky_base(p, &progress);
  progress.finish();
  const NoiseTexture detail = generate_sky_detail(p);
  const NoiseTexture curl = generate_curl_2d(p);
  save_volume(dir / "sky_noise_base.nvdf", noise_to_volume(base, VolumeEncoding::RGBA8, kSkyBaseChannels));
  save_volume(dir / "sky_noise_detail.nvdf", noise_to_volume(detail, VolumeEncoding::RGBA8, kSkyDetailChannels));
  save_volume(dir / "curl_noise.nvdf", noise_to_volume(curl, VolumeEncoding::RGBA8, curl_channels(curl.signed_range)));
  return dir;
}

bool resolve_cloudscapes(ecs::World& world, const fs::path& level_dir) {
  bool any = false;
  world.view<Cloudscape>().each([&](ecs::Entity e, Cloudscape& c) {
    if (const auto* t = static_cast<const ecs::World&>(world).try_get<scene::Transform>(e)) {
      const glm::vec3 s = t->scale;
      if (std::fabs(s.x - s.y) > 1e-4f * std::fabs(s.x) || std::fabs(s.x - s.z) > 1e-4f * std::fabs(s.x) || !(s.x > 0.0f))
        fail("%s: a Cloudscape's Transform needs one positive uniform scale, got (%g, %g, %g)", c.where.c_str(), s.x, s.y,
             s.z);
    }
    any = true;
    if (c.asset.empty()) return;  // a grown cloud's (CloudGrowth): the clouds module checks it has one
    const fs::path p(c.asset);
    c.resolved = prepare_cloudscape_asset((p.is_absolute() ? p : level_dir / p).lexically_normal(), c.where);
  });
  return any;
}

}  // namespace cumulo::clouds
