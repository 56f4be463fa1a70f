#pragma once
// VkPipelineCache persisted on disk (<cache_dir>/pipelines.bin), loaded when the Context starts and
// saved when it ends (or on save()). A file from another device or driver is ignored (the header's
// vendor/device/UUID are checked first), a truncated or garbled file too: it is only a cache.
//
//   VkPipelineCache pc = ctx.pipeline_cache().handle();   // pass to vkCreate*Pipelines
//   ctx.pipeline_cache().save();                          // also done by ~Context
#include <filesystem>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class Context;

class PipelineCache {
 public:
  PipelineCache(Context& ctx, std::filesystem::path file);
  ~PipelineCache();
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  VkPipelineCache handle() const { return cache_; }
  const std::filesystem::path& file() const { return file_; }
  bool loaded_from_disk() const { return loaded_; }
  // Writes the cache atomically (temp file + rename). Failures are logged, never thrown.
  void save();

 private:
  Context& ctx_;
  std::filesystem::path file_;
  VkPipelineCache cache_ = VK_NULL_HANDLE;
  bool loaded_ = false;
};

}  // namespace cumulo::gpu
