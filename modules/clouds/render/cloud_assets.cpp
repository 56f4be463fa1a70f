#include "modules/clouds/render/cloud_assets.h"

#include <cmath>
#include <optional>
#include <vector>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/context.h"
#include "modules/clouds/volume/nvdf.h"
#include "modules/clouds/volume/volume_file.h"

namespace cumulo::clouds::render {
namespace {

namespace fs = std::filesystem;

// A canonical key for a path that exists: two spellings of one folder share a GPU copy.
fs::path canonical_or_fail(const fs::path& p, const char* what) {
  std::error_code ec;
  if (!fs::exists(p, ec)) fail("%s: no such %s", p.string().c_str(), what);
  fs::path c = fs::canonical(p, ec);
  if (ec) fail("%s: %s", p.string().c_str(), ec.message().c_str());
  return c;
}

Volume load_file(const fs::path& folder, std::string_view name) {
  const fs::path file = folder / name;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    fail("%s: missing (a cloudscape folder holds what `cumulo bake` or `cumulo import` writes: %s, %s, %s, %s)",
         file.string().c_str(), std::string(kModelingFileName).c_str(), std::string(kModelingBc1FileName).c_str(),
         std::string(kFieldFileName).c_str(), std::string(kFieldBc1FileName).c_str());
  return load_volume(file);
}

// The shaders read channels by position (r, g, b), so the file's channel order must match.
void check_channel(const Volume& v, uint32_t index, std::string_view semantic, const fs::path& file) {
  if (v.channels.size() <= index || v.channels[index].semantic != semantic)
    fail("%s: channel %u must be '%s' for the renderer (got '%s')", file.string().c_str(), index,
         std::string(semantic).c_str(), v.channels.size() > index ? v.channels[index].semantic.c_str() : "none");
}

void check_sampleable(gpu::Context& ctx, VkFormat format, const fs::path& file) {
  VkFormatProperties props{};
  vkGetPhysicalDeviceFormatProperties(ctx.physical_device(), format, &props);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
  if ((props.optimalTilingFeatures & need) != need)
    fail("%s: %s cannot sample this file's format (%d) with linear filtering; try the other cloud format set",
         file.string().c_str(), ctx.info().name.c_str(), int(format));
}


bool same_bounds(const Volume& a, const Volume& b) {
  auto close = [](glm::vec3 x, glm::vec3 y) { return glm::all(glm::lessThan(glm::abs(x - y), glm::vec3(1e-3f))); };
  return close(a.bounds_min, b.bounds_min) && close(a.bounds_max, b.bounds_max);
}
bool same_box(const Volume& a, const Volume& b) { return a.size == b.size && same_bounds(a, b); }

}  // namespace

gpu::Image upload_volume(gpu::Context& ctx, const Volume& v, VkFormat format, const fs::path& file) {
  check_sampleable(ctx, format, file);
  const std::string name = file.filename().string();
  gpu::Image image(ctx, gpu::ImageDesc::tex3d(v.size.x, v.size.y, v.size.z, format, VK_IMAGE_USAGE_SAMPLED_BIT,
                                              v.mip_count(), name.c_str()));
  std::vector<gpu::MipData> mips;
  for (const auto& level : v.levels) mips.push_back({level.data(), level.size()});
  image.upload(std::span<const gpu::MipData>(mips.data(), mips.size()));
  return image;
}

CloudFormatSet default_format_set(const gpu::DeviceInfo& device) {
  if (device.is_cpu() || !device.texture_compression_bc) return CloudFormatSet::Uncompressed;
  return CloudFormatSet::Compressed;
}

std::shared_ptr<CloudAsset> load_cloud_asset(gpu::Context& ctx, const fs::path& folder_in, const CloudFormats& formats) {
  const fs::path folder = canonical_or_fail(folder_in, "cloudscape folder");
  if (!fs::is_directory(folder))
    fail("%s: a cloudscape asset is a folder of .nvdf files (bake a recipe with `cumulo bake RECIPE -o DIR`)",
         folder_in.string().c_str());
  if ((formats.bc1_modeling || formats.bc1_field) && !ctx.info().texture_compression_bc)
    fail("%s: the compressed cloud formats need BC texture support, which %s lacks", folder.string().c_str(),
         ctx.info().name.c_str());

  const std::string_view modeling_name = formats.bc1_modeling ? kModelingBc1FileName : kModelingFileName;
  const std::string_view field_name = formats.bc1_field ? kFieldBc1FileName : kFieldFileName;
  const fs::path modeling_file = folder / modeling_name, field_file = folder / field_name;
  Volume modeling = load_file(folder, modeling_name);
  Volume field = load_file(folder, field_name);

  const VolumeEncoding want_modeling = formats.bc1_modeling ? VolumeEncoding::BC1 : VolumeEncoding::RGBA8;
  if (modeling.encoding != want_modeling)
    fail("%s: encoding %s, the renderer expects %s here", modeling_file.string().c_str(), encoding_name(modeling.encoding),
         encoding_name(want_modeling));
  check_modeling_volume(modeling, modeling_file.string());
  check_channel(modeling, 0, kDimensionalProfile, modeling_file);
  check_channel(modeling, 1, kDetailType, modeling_file);
  check_channel(modeling, 2, kDensityScale, modeling_file);
  // The coverage thresholds: the RGBA8 alpha where the file declares it (older bakes and imports leave it
  // undeclared: threshold 0, whatever the bytes), else (BC1) coverage.nvdf when the folder has it.
  if (!formats.bc1_modeling && !(modeling.channels.size() > 3 && modeling.channels[3].semantic == kCoverageThreshold))
    for (auto& level : modeling.levels)
      for (size_t i = 3; i < level.size(); i += 4) level[i] = 0;
  std::optional<Volume> coverage;
  const fs::path coverage_file = folder / kCoverageFileName;
  if (formats.bc1_modeling) {
    std::error_code ec;
    if (fs::is_regular_file(coverage_file, ec)) {
      coverage = load_volume(coverage_file);
      if (coverage->encoding != VolumeEncoding::R8)
        fail("%s: encoding %s, the renderer expects r8 here", coverage_file.string().c_str(), encoding_name(coverage->encoding));
      check_channel(*coverage, 0, kCoverageThreshold, coverage_file);
      if (!same_bounds(*coverage, modeling))
        fail("%s: its world box differs from %s's", coverage_file.string().c_str(), modeling_file.filename().string().c_str());
    } else {
      coverage = Volume::create({1, 1, 1}, modeling.voxel_size, VolumeEncoding::R8, {{"r", std::string(kCoverageThreshold)}});
      coverage->bounds_min = modeling.bounds_min, coverage->bounds_max = modeling.bounds_max;
    }
  }

  const VolumeEncoding want_field = formats.bc1_field ? VolumeEncoding::BC1 : VolumeEncoding::R16;
  if (field.encoding != want_field)
    fail("%s: encoding %s, the renderer expects %s here", field_file.string().c_str(), encoding_name(field.encoding),
         encoding_name(want_field));
  check_field_volume(field, field_file.string());
  check_channel(field, 0, kSignedDistance, field_file);
  if (std::fabs(field.channels[0].decode_min - kSdfRangeMin) > 1e-3f || std::fabs(field.channels[0].decode_max - kSdfRangeMax) > 1e-3f)
    fail("%s: SDF decode range %g..%g m, the renderer expects %g..%g m", field_file.string().c_str(),
         field.channels[0].decode_min, field.channels[0].decode_max, kSdfRangeMin, kSdfRangeMax);
  if (!same_box(modeling, field))
    fail("%s: size %ux%ux%u or bounds differ from %s's %ux%ux%u", field_file.string().c_str(), field.size.x,
         field.size.y, field.size.z, modeling_file.filename().string().c_str(), modeling.size.x, modeling.size.y,
         modeling.size.z);

  // The fair-weather field (volume/nvdf.h), when the bake wrote one; else one texel at the decode minimum, which the
  // march reads as "inside" and so falls back to the field.
  const fs::path fair_file = folder / kFieldFairFileName;
  Volume fair;
  bool has_fair = false;
  {
    std::error_code ec;
    if (fs::is_regular_file(fair_file, ec)) {
      fair = load_volume(fair_file);
      if (fair.encoding != VolumeEncoding::R16)
        fail("%s: encoding %s, the renderer expects r16 here", fair_file.string().c_str(), encoding_name(fair.encoding));
      check_channel(fair, 0, kSignedDistance, fair_file);
      if (std::fabs(fair.channels[0].decode_min - kSdfRangeMin) > 1e-3f || std::fabs(fair.channels[0].decode_max - kSdfRangeMax) > 1e-3f)
        fail("%s: SDF decode range %g..%g m, the renderer expects %g..%g m", fair_file.string().c_str(),
             fair.channels[0].decode_min, fair.channels[0].decode_max, kSdfRangeMin, kSdfRangeMax);
      if (!same_bounds(fair, modeling))
        fail("%s: its world box differs from %s's", fair_file.string().c_str(), modeling_file.filename().string().c_str());
      has_fair = true;
    } else {
      fair = Volume::create({1, 1, 1}, modeling.voxel_size, VolumeEncoding::R16,
                            {{"r", std::string(kSignedDistance), kSdfRangeMin, kSdfRangeMax}});
      fair.bounds_min = modeling.bounds_min, fair.bounds_max = modeling.bounds_max;
    }
  }

  auto asset = std::make_shared<CloudAsset>();
  asset->folder = folder;
  asset->formats = formats;
  asset->dims = modeling.size;
  asset->voxel_size = modeling.voxel_size;
  asset->bounds_min = modeling.bounds_min;
  asset->bounds_max = modeling.bounds_max;
  asset->modeling = upload_volume(ctx, modeling, formats.bc1_modeling ? VK_FORMAT_BC1_RGB_UNORM_BLOCK : VK_FORMAT_R8G8B8A8_UNORM,
                                  modeling_file);
  asset->field = upload_volume(ctx, field, formats.bc1_field ? VK_FORMAT_BC1_RGB_UNORM_BLOCK : VK_FORMAT_R16_UNORM, field_file);
  if (coverage) asset->coverage = upload_volume(ctx, *coverage, VK_FORMAT_R8_UNORM, coverage_file);
  asset->field_fair = upload_volume(ctx, fair, VK_FORMAT_R16_UNORM, fair_file);
  asset->has_field_fair = has_fair;
  asset->gpu_bytes = modeling.payload_bytes() + field.payload_bytes() + (coverage ? coverage->payload_bytes() : 0) +
                     (has_fair ? fair.payload_bytes() : 0);
  LOG_INFO("clouds: %s on the GPU (%s%s + %s%s, %ux%ux%u, %.2f MB)", folder.string().c_str(),
           std::string(modeling_name).c_str(), coverage ? " + coverage" : "", std::string(field_name).c_str(),
           has_fair ? " + field_fair" : "", asset->dims.x, asset->dims.y, asset->dims.z, double(asset->gpu_bytes) / 1e6);
  return asset;
}

std::shared_ptr<CloudNoise> load_cloud_noise(gpu::Context& ctx, const fs::path& file_in) {
  const fs::path file = canonical_or_fail(file_in, "noise file");
  Volume v = load_volume(file);
  if (v.encoding != VolumeEncoding::RGBA8)
    fail("%s: encoding %s; the cloud renderer samples RGBA8 voxel noise (write it with `cumulo noise --format 8`)",
         file.string().c_str(), encoding_name(v.encoding));
  if (v.channels.size() != 4)
    fail("%s: %zu channels, the voxel noise has 4 (Curly-Alligator low/high, Alligator low/high)", file.string().c_str(),
         v.channels.size());
  if (v.size.x != v.size.y || v.size.y != v.size.z)
    fail("%s: the voxel noise must be a cube, got %ux%ux%u", file.string().c_str(), v.size.x, v.size.y, v.size.z);
  auto noise = std::make_shared<CloudNoise>();
  noise->file = file;
  noise->size = v.size.x;
  noise->mips = v.mip_count();
  noise->gpu_bytes = v.payload_bytes();
  noise->image = upload_volume(ctx, v, VK_FORMAT_R8G8B8A8_UNORM, file);
  return noise;
}

std::shared_ptr<const CloudAsset> CloudAssetCache::cloudscape(const fs::path& folder, const CloudFormats& formats) {
  // Asked every frame: resolve each spelling of a folder once, not with realpath calls per frame.
  auto alias = aliases_.find(folder.string());
  if (alias == aliases_.end())
    alias = aliases_.emplace(folder.string(), canonical_or_fail(folder, "cloudscape folder").string()).first;
  const std::string& key = alias->second;
  auto it = assets_.find({key, formats});
  if (it != assets_.end()) return it->second;
  std::shared_ptr<const CloudAsset> a = load_cloud_asset(ctx_, key, formats);
  assets_.emplace(std::make_pair(key, formats), a);
  return a;
}

std::shared_ptr<const CloudNoise> CloudAssetCache::noise(const fs::path& file) {
  const std::string key = canonical_or_fail(file, "noise file").string();
  auto it = noises_.find(key);
  if (it != noises_.end()) return it->second;
  std::shared_ptr<const CloudNoise> n = load_cloud_noise(ctx_, key);
  noises_.emplace(key, n);
  return n;
}

uint64_t CloudAssetCache::gpu_bytes() const {
  uint64_t total = 0;
  for (const auto& [k, a] : assets_) total += a->gpu_bytes;
  for (const auto& [k, n] : noises_) total += n->gpu_bytes;
  return total;
}

}  // namespace cumulo::clouds::render
