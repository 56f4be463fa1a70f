#pragma once
// Cloud assets on the GPU: a cloudscape folder of NVDFs (what `cumulo bake` / `cumulo import` write,
// modules/clouds/volume/nvdf.h) and the voxel noise (`cumulo noise`: voxel_noise.nvdf) as sampled 3D
// images, one GPU copy per (canonical path, formats).
//
//   clouds::render::CloudAssetCache cache(ctx);
//   auto formats = clouds::render::default_cloud_formats(ctx.info());      // CPU device -> uncompressed
//   std::shared_ptr<const CloudAsset> sky = cache.cloudscape("build/content/sample/cloudscape", formats);
//   std::shared_ptr<const CloudNoise> noise = cache.noise("build/content/sample/noise/voxel_noise.nvdf");
//   // a second entity naming the same folder (any spelling of the path) gets the same CloudAsset
//
// Format sets (LAVAPIPE.md: BC1 fetches are ~1.7x slower than R8/R16 on a CPU device; on GPUs the
// compressed set is the talk's memory budget):
//   compressed    modeling_bc1.nvdf (BC1 RGB)  + coverage.nvdf (R8, half resolution) + field_bc1.nvdf
//                 (conservative BC1 SDF)                                                 GPUs
//   uncompressed  modeling.nvdf (RGBA8, a = coverage threshold) + field.nvdf (R16 unorm)   CPU devices
// Coverage thresholds (nvdf.h): a folder without coverage.nvdf, or a modeling.nvdf without the alpha channel
// (imports, older bakes), loads with threshold 0 everywhere.
// The modeling and SDF choices are independent (CloudFormats), so the 16-bit vs BC1 SDF ablation keeps
// the modeling data fixed. Every error is a cumulo::Error naming the file.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include <glm/glm.hpp>

#include "engine/core/enum_names.h"
#include "engine/gpu/image.h"
#include "modules/clouds/volume/volume.h"

namespace cumulo::gpu {
class Context;
struct DeviceInfo;
}  // namespace cumulo::gpu

namespace cumulo::clouds::render {

enum class CloudFormatSet { Compressed, Uncompressed };
inline constexpr std::array kCloudFormatSetNames{EnumName<CloudFormatSet>{CloudFormatSet::Compressed, "compressed"},
                                                 EnumName<CloudFormatSet>{CloudFormatSet::Uncompressed, "uncompressed"}};
inline const char* format_set_name(CloudFormatSet s) { return name_of(kCloudFormatSetNames, s); }

struct CloudFormats {
  bool bc1_modeling = false;  // modeling_bc1.nvdf (BC1) instead of modeling.nvdf (RGBA8)
  bool bc1_field = false;     // field_bc1.nvdf (conservative BC1) instead of field.nvdf (R16)
  static CloudFormats from_set(CloudFormatSet s) {
    return s == CloudFormatSet::Compressed ? CloudFormats{true, true} : CloudFormats{false, false};
  }
  auto operator<=>(const CloudFormats&) const = default;
};
// Uncompressed on CPU devices, compressed elsewhere (when the device samples BC1).
CloudFormatSet default_format_set(const gpu::DeviceInfo& device);
inline CloudFormats default_cloud_formats(const gpu::DeviceInfo& device) {
  return CloudFormats::from_set(default_format_set(device));
}

// One cloudscape asset on the GPU (immutable once loaded; shared by every instance that names it). A grown cloud's
// asset (cloud_growth_runtime.h) borrows its images instead: `borrowed` names images owned elsewhere, which change
// as the cloud grows. Whatever reads the images goes through modeling_image(), field_image(), field_fair_image().
struct CloudAsset {
  std::filesystem::path folder;  // canonical (a grown cloud: its grow spec, for messages)
  CloudFormats formats;
  gpu::Image modeling;  // 3D: r profile, g detail type, b density scale (RGBA8: a coverage threshold)
  gpu::Image coverage;  // 3D R8: the coverage thresholds of the BC1 modeling (compressed only; 1 texel of 0 without the file)
  gpu::Image field;     // 3D: signed distance (R16 0..1 <-> -256..4096 m, or conservative BC1 rgb)
  gpu::Image field_fair;  // 3D R16: the fair-weather field (volume/nvdf.h); 1 texel of -256 m without the file
  bool has_field_fair = false;
  // Images owned elsewhere (null: the owned ones above), live as long as this asset, uncompressed formats.
  struct Borrowed {
    const gpu::Image* modeling = nullptr;
    const gpu::Image* field = nullptr;
    const gpu::Image* field_fair = nullptr;
  } borrowed;
  const gpu::Image& modeling_image() const { return borrowed.modeling ? *borrowed.modeling : modeling; }
  const gpu::Image& field_image() const { return borrowed.field ? *borrowed.field : field; }
  const gpu::Image& field_fair_image() const { return borrowed.field_fair ? *borrowed.field_fair : field_fair; }
  glm::uvec3 dims{0};
  float voxel_size = 0.0f;
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // the asset's own world box (metres)
  uint64_t gpu_bytes = 0;                        // texel bytes of both images
  // +1 whenever the images change under the same asset (a growing cloud's update, from the frame whose graph
  // rebuilds them): what derives from them beside the light grid (the path tracer's majorant grid) follows it.
  uint64_t revision = 0;
};

// The voxel noise: 4 channels (R/G Curly-Alligator low/high, B/A Alligator low/high), full mips,
// RGBA8 (`cumulo noise`'s default). The talk's 4-bit R4G4B4A4 file is refused with a message for now.
struct CloudNoise {
  std::filesystem::path file;  // canonical
  gpu::Image image;
  uint32_t size = 0, mips = 0;
  uint64_t gpu_bytes = 0;
  VkImageView view() const { return image.view(); }
};

// Loaders (no caching): throw cumulo::Error("<file>: ...").
std::shared_ptr<CloudAsset> load_cloud_asset(gpu::Context& ctx, const std::filesystem::path& folder,
                                             const CloudFormats& formats);
std::shared_ptr<CloudNoise> load_cloud_noise(gpu::Context& ctx, const std::filesystem::path& file);
// A volume's texels and mips into a sampled 3D image of `format` (checked sampleable with linear filtering).
gpu::Image upload_volume(gpu::Context& ctx, const Volume& v, VkFormat format, const std::filesystem::path& file);

// One GPU copy per canonical path (and formats). Entries live as long as the cache.
class CloudAssetCache {
 public:
  explicit CloudAssetCache(gpu::Context& ctx) : ctx_(ctx) {}
  std::shared_ptr<const CloudAsset> cloudscape(const std::filesystem::path& folder, const CloudFormats& formats);
  std::shared_ptr<const CloudNoise> noise(const std::filesystem::path& file);
  size_t size() const { return assets_.size() + noises_.size(); }
  uint64_t gpu_bytes() const;

 private:
  gpu::Context& ctx_;
  std::map<std::pair<std::string, CloudFormats>, std::shared_ptr<const CloudAsset>> assets_;
  std::map<std::string, std::shared_ptr<const CloudNoise>> noises_;
  std::map<std::string, std::string> aliases_;  // folder as given -> canonical
};

}  // namespace cumulo::clouds::render
