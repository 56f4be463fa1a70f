#include "engine/gpu/pipeline_cache.h"

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <vector>

#include "engine/core/log.h"
#include "engine/gpu/context.h"

namespace cumulo::gpu {

namespace fs = std::filesystem;

static std::vector<char> read_cache_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return {};
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

PipelineCache::PipelineCache(Context& ctx, fs::path file) : ctx_(ctx), file_(std::move(file)) {
  std::vector<char> data = read_cache_file(file_);
  // Check the header ourselves: a blob from another device must not be handed to the driver.
  if (data.size() >= sizeof(VkPipelineCacheHeaderVersionOne)) {
    VkPipelineCacheHeaderVersionOne h;
    std::memcpy(&h, data.data(), sizeof h);
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(ctx.physical_device(), &p);
    bool ok = h.headerSize >= sizeof h && h.headerVersion == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
              h.vendorID == p.vendorID && h.deviceID == p.deviceID &&
              std::memcmp(h.pipelineCacheUUID, p.pipelineCacheUUID, VK_UUID_SIZE) == 0;
    if (!ok) {
      LOG_INFO("gpu: pipeline cache %s is from another device or driver; starting empty", file_.string().c_str());
      data.clear();
    }
  } else if (!data.empty()) {
    LOG_WARN("gpu: pipeline cache %s is truncated (%zu bytes); starting empty", file_.string().c_str(), data.size());
    data.clear();
  }
  VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  info.initialDataSize = data.size();
  info.pInitialData = data.empty() ? nullptr : data.data();
  if (vkCreatePipelineCache(ctx.device(), &info, nullptr, &cache_) != VK_SUCCESS) {
    info.initialDataSize = 0;
    info.pInitialData = nullptr;
    VK_CHECK(vkCreatePipelineCache(ctx.device(), &info, nullptr, &cache_));
  } else {
    loaded_ = !data.empty();
  }
  if (loaded_) LOG_DEBUG("gpu: loaded pipeline cache %s (%zu bytes)", file_.string().c_str(), data.size());
}

PipelineCache::~PipelineCache() {
  save();
  vkDestroyPipelineCache(ctx_.device(), cache_, nullptr);
}

void PipelineCache::save() {
  size_t size = 0;
  if (vkGetPipelineCacheData(ctx_.device(), cache_, &size, nullptr) != VK_SUCCESS || size == 0) return;
  std::vector<char> data(size);
  if (vkGetPipelineCacheData(ctx_.device(), cache_, &size, data.data()) != VK_SUCCESS) return;
  data.resize(size);
  std::error_code ec;
  fs::create_directories(file_.parent_path(), ec);
  // A per-process temp name: several test processes may save the same cache at once; rename is atomic.
  fs::path tmp = file_;
  tmp += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) {
      LOG_WARN("gpu: cannot write pipeline cache %s", tmp.string().c_str());
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, file_, ec);
  if (ec) {
    LOG_WARN("gpu: cannot save pipeline cache %s: %s", file_.string().c_str(), ec.message().c_str());
    fs::remove(tmp, ec);
  }
}

}  // namespace cumulo::gpu
