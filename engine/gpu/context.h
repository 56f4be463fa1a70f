#pragma once
// gpu::Context: Vulkan instance, device, one graphics+compute(+present) queue, validation counting,
// debug names/labels, one-off submission, and the shared services every resource needs
// (memory allocator, sampler cache, pipeline cache).
//
//   gpu::ContextDesc desc;                       // validation forced on by CUMULO_VALIDATION=1 / Debug builds
//   desc.instance_extensions = glfw_extensions;  // optional: from glfwGetRequiredInstanceExtensions
//   desc.need_present = true;                    // optional: then give create_surface
//   desc.create_surface = [&](VkInstance i) { VkSurfaceKHR s; glfwCreateWindowSurface(i, win, nullptr, &s); return s;
//   }; gpu::Context ctx(desc); ctx.submit_and_wait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buf, 0,
//   VK_WHOLE_SIZE, 0); }); ctx.set_name(buf, "my buffer");              // no-op without VK_EXT_debug_utils
//   EXPECT_EQ(ctx.validation_errors(), 0u);      // every validation message is counted and logged
//
// Device choice: discrete > integrated > virtual > CPU (lavapipe); override with env
// CUMULO_DEVICE=<index or case-insensitive substring of the device name> (or desc.device).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/gpu/vk.h"

namespace cumulo::gpu {

class MemoryAllocator;
class SamplerCache;
class PipelineCache;

struct ContextDesc {
  bool validation = false;                                 // also on with env CUMULO_VALIDATION=1 or in Debug builds
  std::vector<std::string> instance_extensions;            // e.g. from glfwGetRequiredInstanceExtensions
  bool need_present = false;                               // require a queue family that presents to the surface
  std::function<VkSurfaceKHR(VkInstance)> create_surface;  // called once after instance creation; ctx owns the surface
  std::string device;                                      // device override; empty: env CUMULO_DEVICE
  std::string app_name = "cumulo";
  // Folder for the pipeline cache (pipelines.bin) and the shader cache (shaders/*.spv). Empty:
  // $CUMULO_CACHE_DIR, else $XDG_CACHE_HOME/cumulo, else $HOME/.cache/cumulo.
  std::filesystem::path cache_dir;
};

// What was chosen, for logs and the stats JSON.
struct DeviceInfo {
  std::string name;         // "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string driver_name;  // "llvmpipe"
  std::string driver_info;  // "Mesa 22.3.6 (LLVM 15.0.6)"
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t api_version = 0;
  VkPhysicalDeviceLimits limits{};
  bool is_cpu() const { return type == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  // Optional features/extensions actually enabled.
  bool texture_compression_bc = false;
  bool push_descriptors = false;
  uint32_t max_push_descriptors = 0;  // VkPhysicalDevicePushDescriptorPropertiesKHR (lavapipe: 32)
  bool storage_image_write_without_format = false;
  bool sampler_anisotropy = false;
  bool timestamps = false;  // timestampValidBits > 0 on our queue
};

const char* device_type_name(VkPhysicalDeviceType type);

// $CUMULO_CACHE_DIR, else $XDG_CACHE_HOME/cumulo, else $HOME/.cache/cumulo (else a temp folder).
std::filesystem::path default_cache_dir();

// Process-wide validation error/warning counts over all Contexts, including messages emitted while
// a Context is being destroyed (leaked objects): tests check this after the Context is gone.
uint32_t total_validation_errors();
uint32_t total_validation_warnings();

class Context {
 public:
  explicit Context(const ContextDesc& desc = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  VkSurfaceKHR surface() const { return surface_; }  // VK_NULL_HANDLE unless create_surface was given
  const DeviceInfo& info() const { return info_; }
  const std::filesystem::path& cache_dir() const { return cache_dir_; }

  // Validation: counts of messages since creation (errors and warnings separately).
  bool validation_enabled() const { return validation_; }
  uint32_t validation_errors() const { return errors_.load(); }
  uint32_t validation_warnings() const { return warnings_.load(); }
  std::string last_validation_message() const;

  // Debug utils (no-ops without VK_EXT_debug_utils).
  bool debug_utils() const { return set_name_fn_ != nullptr; }
  void set_name(VkObjectType type, uint64_t handle, const char* name) const;
  template <class H>
  void set_name(H handle, const char* name) const;
  void set_name(VkObjectType type, uint64_t handle, const std::string& name) const {
    set_name(type, handle, name.c_str());
  }
  template <class H>
  void set_name(H handle, const std::string& name) const {
    set_name(handle, name.c_str());
  }
  void cmd_begin_label(VkCommandBuffer cmd, const char* name, const float color[4] = nullptr) const;
  void cmd_end_label(VkCommandBuffer cmd) const;

  // Queue access is serialized; use submit() rather than vkQueueSubmit2 directly.
  void submit(const VkSubmitInfo2& info, VkFence fence) const;
  // Records with `record`, submits, waits for completion. For uploads, readbacks, tests.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);
  void wait_idle() const;
  std::mutex& queue_mutex() const { return queue_mutex_; }

  MemoryAllocator& allocator() { return *allocator_; }
  SamplerCache& samplers() { return *samplers_; }
  PipelineCache& pipeline_cache() { return *pipeline_cache_; }

  // Extension entry points (null when unavailable).
  PFN_vkCmdPushDescriptorSetKHR cmd_push_descriptor_set = nullptr;

 private:
  static VkBool32 VKAPI_PTR debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                           VkDebugUtilsMessageTypeFlagsEXT types,
                                           const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  void destroy();
  void create_instance(const ContextDesc& desc);
  void pick_device(const ContextDesc& desc);
  void create_device(const ContextDesc& desc);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  DeviceInfo info_;
  std::filesystem::path cache_dir_;
  bool validation_ = false;
  std::atomic<uint32_t> errors_{0}, warnings_{0};
  mutable std::mutex message_mutex_;
  std::string last_message_;
  mutable std::mutex queue_mutex_;
  std::mutex oneoff_mutex_;
  VkCommandPool oneoff_pool_ = VK_NULL_HANDLE;
  VkFence oneoff_fence_ = VK_NULL_HANDLE;
  PFN_vkSetDebugUtilsObjectNameEXT set_name_fn_ = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT begin_label_fn_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT end_label_fn_ = nullptr;
  std::unique_ptr<MemoryAllocator> allocator_;
  std::unique_ptr<SamplerCache> samplers_;
  std::unique_ptr<PipelineCache> pipeline_cache_;
};

// Debug label scope: ScopedLabel label(ctx, cmd, "clouds");  (ends at scope exit)
class ScopedLabel {
 public:
  ScopedLabel(const Context& ctx, VkCommandBuffer cmd, const char* name, const float color[4] = nullptr)
      : ctx_(ctx), cmd_(cmd) {
    ctx.cmd_begin_label(cmd, name, color);
  }
  ~ScopedLabel() { ctx_.cmd_end_label(cmd_); }
  ScopedLabel(const ScopedLabel&) = delete;
  ScopedLabel& operator=(const ScopedLabel&) = delete;

 private:
  const Context& ctx_;
  VkCommandBuffer cmd_;
};

// Maps a Vulkan handle type to its VkObjectType (for set_name).
template <class H>
constexpr VkObjectType object_type_of() {
  if constexpr (std::is_same_v<H, VkBuffer>)
    return VK_OBJECT_TYPE_BUFFER;
  else if constexpr (std::is_same_v<H, VkImage>)
    return VK_OBJECT_TYPE_IMAGE;
  else if constexpr (std::is_same_v<H, VkImageView>)
    return VK_OBJECT_TYPE_IMAGE_VIEW;
  else if constexpr (std::is_same_v<H, VkSampler>)
    return VK_OBJECT_TYPE_SAMPLER;
  else if constexpr (std::is_same_v<H, VkPipeline>)
    return VK_OBJECT_TYPE_PIPELINE;
  else if constexpr (std::is_same_v<H, VkPipelineLayout>)
    return VK_OBJECT_TYPE_PIPELINE_LAYOUT;
  else if constexpr (std::is_same_v<H, VkShaderModule>)
    return VK_OBJECT_TYPE_SHADER_MODULE;
  else if constexpr (std::is_same_v<H, VkDescriptorSetLayout>)
    return VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT;
  else if constexpr (std::is_same_v<H, VkDescriptorSet>)
    return VK_OBJECT_TYPE_DESCRIPTOR_SET;
  else if constexpr (std::is_same_v<H, VkDescriptorPool>)
    return VK_OBJECT_TYPE_DESCRIPTOR_POOL;
  else if constexpr (std::is_same_v<H, VkCommandBuffer>)
    return VK_OBJECT_TYPE_COMMAND_BUFFER;
  else if constexpr (std::is_same_v<H, VkCommandPool>)
    return VK_OBJECT_TYPE_COMMAND_POOL;
  else if constexpr (std::is_same_v<H, VkFence>)
    return VK_OBJECT_TYPE_FENCE;
  else if constexpr (std::is_same_v<H, VkSemaphore>)
    return VK_OBJECT_TYPE_SEMAPHORE;
  else if constexpr (std::is_same_v<H, VkQueryPool>)
    return VK_OBJECT_TYPE_QUERY_POOL;
  else if constexpr (std::is_same_v<H, VkDeviceMemory>)
    return VK_OBJECT_TYPE_DEVICE_MEMORY;
  else if constexpr (std::is_same_v<H, VkSwapchainKHR>)
    return VK_OBJECT_TYPE_SWAPCHAIN_KHR;
  else if constexpr (std::is_same_v<H, VkQueue>)
    return VK_OBJECT_TYPE_QUEUE;
  else
    static_assert(sizeof(H) == 0, "add this handle type to object_type_of");
}

template <class H>
void Context::set_name(H handle, const char* name) const {
  set_name(object_type_of<H>(), reinterpret_cast<uint64_t>(handle), name);
}

}  // namespace cumulo::gpu
