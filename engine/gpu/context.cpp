#include "engine/gpu/context.h"

#include "engine/core/file_lock.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/gpu/allocator.h"
#include "engine/gpu/detail/device_select.h"
#include "engine/gpu/pipeline_cache.h"
#include "engine/gpu/sampler.h"

namespace cumulo::gpu {

namespace fs = std::filesystem;

const char* vk_result_name(VkResult r) {
  switch (r) {
#define CASE(x) \
  case x:       \
    return #x;
    CASE(VK_SUCCESS)
    CASE(VK_NOT_READY)
    CASE(VK_TIMEOUT)
    CASE(VK_EVENT_SET)
    CASE(VK_EVENT_RESET)
    CASE(VK_INCOMPLETE)
    CASE(VK_ERROR_OUT_OF_HOST_MEMORY) CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY) CASE(VK_ERROR_INITIALIZATION_FAILED)
        CASE(VK_ERROR_DEVICE_LOST) CASE(VK_ERROR_MEMORY_MAP_FAILED) CASE(VK_ERROR_LAYER_NOT_PRESENT)
            CASE(VK_ERROR_EXTENSION_NOT_PRESENT) CASE(VK_ERROR_FEATURE_NOT_PRESENT) CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
                CASE(VK_ERROR_TOO_MANY_OBJECTS) CASE(VK_ERROR_FORMAT_NOT_SUPPORTED) CASE(VK_ERROR_FRAGMENTED_POOL)
                    CASE(VK_ERROR_OUT_OF_POOL_MEMORY) CASE(VK_ERROR_SURFACE_LOST_KHR)
                        CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR) CASE(VK_SUBOPTIMAL_KHR) CASE(VK_ERROR_OUT_OF_DATE_KHR)
                            CASE(VK_ERROR_VALIDATION_FAILED_EXT)
#undef CASE
                                default : return "VK_ERROR_UNKNOWN";
  }
}

void vk_fail(VkResult r, const char* expr, const char* file, int line) {
  throw Error(strf("%s failed: %s (%s:%d)", expr, vk_result_name(r), file, line));
}

const char* device_type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

static bool env_flag(const char* name, bool* value) {
  const char* v = std::getenv(name);
  if (!v || !*v) return false;
  *value = !(std::strcmp(v, "0") == 0 || std::strcmp(v, "false") == 0 || std::strcmp(v, "off") == 0);
  return true;
}

fs::path default_cache_dir() { return cumulo::cache_dir(); }

static bool has_extension(const std::vector<VkExtensionProperties>& exts, const char* name) {
  for (auto& e : exts)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

static std::vector<VkExtensionProperties> instance_extensions(const char* layer) {
  uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> v(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, v.data());
  v.resize(n);
  return v;
}

static std::atomic<uint32_t> g_total_errors{0}, g_total_warnings{0};
uint32_t total_validation_errors() { return g_total_errors.load(); }
uint32_t total_validation_warnings() { return g_total_warnings.load(); }

VkBool32 VKAPI_PTR Context::debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                           VkDebugUtilsMessageTypeFlagsEXT,
                                           const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  const char* msg = data && data->pMessage ? data->pMessage : "(no message)";
  if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    self->errors_++;
    g_total_errors++;
    LOG_ERROR("vulkan validation: %s", msg);
  } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    self->warnings_++;
    g_total_warnings++;
    LOG_WARN("vulkan validation: %s", msg);
  } else {
    LOG_DEBUG("vulkan: %s", msg);
    return VK_FALSE;
  }
  std::lock_guard lock(self->message_mutex_);
  self->last_message_ = msg;
  return VK_FALSE;  // never abort the call: the count is what tests check
}

std::string Context::last_validation_message() const {
  std::lock_guard lock(message_mutex_);
  return last_message_;
}

Context::Context(const ContextDesc& desc) {
#ifdef NDEBUG
  validation_ = desc.validation;
#else
  validation_ = true;  // Debug builds always validate
#endif
  bool env = false;
  if (env_flag("CUMULO_VALIDATION", &env)) validation_ = validation_ || env;
  cache_dir_ = desc.cache_dir.empty() ? default_cache_dir() : desc.cache_dir;
  try {
    create_instance(desc);
    if (desc.create_surface) {
      surface_ = desc.create_surface(instance_);
      if (!surface_) fail("gpu: create_surface returned no surface");
    } else if (desc.need_present) {
      fail("gpu: ContextDesc::need_present needs create_surface");
    }
    pick_device(desc);
    create_device(desc);
    allocator_ = std::make_unique<MemoryAllocator>(physical_, device_);
    samplers_ = std::make_unique<SamplerCache>(*this);
    pipeline_cache_ = std::make_unique<PipelineCache>(*this, cache_dir_ / "pipelines.bin");
  } catch (...) {
    destroy();  // a throwing constructor never runs ~Context: release what was created
    throw;
  }
}

Context::~Context() { destroy(); }

void Context::destroy() {
  if (device_) vkDeviceWaitIdle(device_);
  pipeline_cache_.reset();
  samplers_.reset();
  allocator_.reset();
  if (oneoff_fence_) vkDestroyFence(device_, oneoff_fence_, nullptr);
  if (oneoff_pool_) vkDestroyCommandPool(device_, oneoff_pool_, nullptr);
  oneoff_fence_ = VK_NULL_HANDLE;
  oneoff_pool_ = VK_NULL_HANDLE;
  if (device_) vkDestroyDevice(device_, nullptr);
  device_ = VK_NULL_HANDLE;
  if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
  surface_ = VK_NULL_HANDLE;
  if (messenger_) {
    auto destroy =
        (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT");
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
}

void Context::create_instance(const ContextDesc& desc) {
  uint32_t loader_version = 0;
  vkEnumerateInstanceVersion(&loader_version);
  if (loader_version < VK_API_VERSION_1_3)
    fail("gpu: the Vulkan loader supports %u.%u, cumulo needs 1.3", VK_API_VERSION_MAJOR(loader_version),
         VK_API_VERSION_MINOR(loader_version));

  std::vector<const char*> layers;
  std::vector<std::string> ext_names = desc.instance_extensions;
  auto available = instance_extensions(nullptr);
  bool debug_utils = has_extension(available, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  bool validation_features = false;
  if (validation_) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> lp(n);
    vkEnumerateInstanceLayerProperties(&n, lp.data());
    bool found = std::any_of(lp.begin(), lp.end(),
                             [](auto& l) { return std::strcmp(l.layerName, "VK_LAYER_KHRONOS_validation") == 0; });
    if (!found) {
      LOG_WARN(
          "gpu: validation requested but VK_LAYER_KHRONOS_validation is not installed (Debian: "
          "vulkan-validationlayers)");
      validation_ = false;
    } else {
      layers.push_back("VK_LAYER_KHRONOS_validation");
      auto layer_exts = instance_extensions("VK_LAYER_KHRONOS_validation");
      validation_features = has_extension(layer_exts, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      if (validation_features) ext_names.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      if (!debug_utils && has_extension(layer_exts, VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) debug_utils = true;
    }
  }
  if (debug_utils) ext_names.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (desc.need_present || desc.create_surface) {
    if (std::find(ext_names.begin(), ext_names.end(), VK_KHR_SURFACE_EXTENSION_NAME) == ext_names.end())
      ext_names.push_back(VK_KHR_SURFACE_EXTENSION_NAME);
  }
  std::sort(ext_names.begin(), ext_names.end());
  ext_names.erase(std::unique(ext_names.begin(), ext_names.end()), ext_names.end());
  std::vector<const char*> exts;
  for (auto& e : ext_names) exts.push_back(e.c_str());

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = desc.app_name.c_str();
  app.pEngineName = "cumulo";
  app.apiVersion = VK_API_VERSION_1_3;

  VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = &Context::debug_callback;
  messenger.pUserData = this;

  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(exts.size());
  info.ppEnabledExtensionNames = exts.data();
  // The messenger in pNext also reports problems during vkCreateInstance/vkDestroyInstance.
  const void* chain = nullptr;
  if (validation_ && debug_utils) {
    messenger.pNext = chain;
    chain = &messenger;
  }
  if (validation_ && validation_features) {
    features.pNext = chain;
    chain = &features;
  }
  info.pNext = chain;
  VkResult r = vkCreateInstance(&info, nullptr, &instance_);
  if (r != VK_SUCCESS) {
    std::string list;
    for (auto* e : exts) list += std::string(" ") + e;
    fail("gpu: vkCreateInstance failed: %s (extensions:%s)", vk_result_name(r), list.c_str());
  }
  if (validation_ && debug_utils) {
    messenger.pNext = nullptr;
    auto create =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT");
    if (create) VK_CHECK(create(instance_, &messenger, nullptr, &messenger_));
  }
  if (debug_utils) {
    set_name_fn_ = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT");
    begin_label_fn_ =
        (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT");
    end_label_fn_ = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT");
    if (!set_name_fn_ || !begin_label_fn_ || !end_label_fn_)
      set_name_fn_ = nullptr, begin_label_fn_ = nullptr, end_label_fn_ = nullptr;
  }
  if (validation_)
    LOG_DEBUG("gpu: validation on (synchronization validation %s)", validation_features ? "on" : "unavailable");
}

namespace {
struct Candidate {
  VkPhysicalDevice device;
  uint32_t family = UINT32_MAX;
  detail::DeviceCandidate desc;
};
}  // namespace

void Context::pick_device(const ContextDesc& desc) {
  uint32_t n = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &n, nullptr));
  std::vector<VkPhysicalDevice> devs(n);
  VK_CHECK(vkEnumeratePhysicalDevices(instance_, &n, devs.data()));
  std::vector<Candidate> cands;
  std::vector<detail::DeviceCandidate> descs;
  for (VkPhysicalDevice d : devs) {
    Candidate c{d};
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    c.desc.name = p.deviceName;
    c.desc.type = p.deviceType;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    if (p.apiVersion >= VK_API_VERSION_1_3) {
      f12.pNext = &f13;
      f2.pNext = &f12;
      vkGetPhysicalDeviceFeatures2(d, &f2);
    }
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, qf.data());
    for (uint32_t i = 0; i < qn && c.family == UINT32_MAX; ++i) {
      VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
      if ((qf[i].queueFlags & need) != need) continue;
      if (surface_) {
        VkBool32 present = VK_FALSE;
        vkGetPhysicalDeviceSurfaceSupportKHR(d, i, surface_, &present);
        if (!present && desc.need_present) continue;
      }
      c.family = i;
    }
    std::string why;
    if (p.apiVersion < VK_API_VERSION_1_3)
      why = "Vulkan 1.3 not supported";
    else if (!f13.synchronization2)
      why = "no synchronization2";
    else if (!f13.dynamicRendering)
      why = "no dynamicRendering";
    else if (!f12.timelineSemaphore)
      why = "no timelineSemaphore";
    else if (!f12.hostQueryReset)
      why = "no hostQueryReset";
    else if (c.family == UINT32_MAX)
      why = desc.need_present ? "no graphics+compute queue that presents to the surface" : "no graphics+compute queue";
    c.desc.suitable = why.empty();
    c.desc.why_not = why;
    descs.push_back(c.desc);
    cands.push_back(c);
  }
  std::string spec = desc.device;
  if (spec.empty())
    if (const char* e = std::getenv("CUMULO_DEVICE")) spec = e;
  int chosen = detail::choose_device(descs, spec);
  physical_ = cands[chosen].device;
  queue_family_ = cands[chosen].family;
}

void Context::create_device(const ContextDesc& desc) {
  VkPhysicalDevicePushDescriptorPropertiesKHR push{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PUSH_DESCRIPTOR_PROPERTIES_KHR};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &driver;
  vkGetPhysicalDeviceProperties2(physical_, &props);
  info_.name = props.properties.deviceName;
  info_.type = props.properties.deviceType;
  info_.api_version = props.properties.apiVersion;
  info_.limits = props.properties.limits;
  info_.driver_name = driver.driverName;
  info_.driver_info = driver.driverInfo;

  uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> avail(n);
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &n, avail.data());
  std::vector<const char*> exts;
  if (desc.need_present || surface_) {
    if (!has_extension(avail, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
      fail("gpu: %s has no VK_KHR_swapchain", info_.name.c_str());
    exts.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  }
  if (has_extension(avail, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) {
    exts.push_back(VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
    info_.push_descriptors = true;
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &push;
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    info_.max_push_descriptors = push.maxPushDescriptors;
  }

  VkPhysicalDeviceVulkan12Features s12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features s13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 sup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  s12.pNext = &s13;
  sup.pNext = &s12;
  vkGetPhysicalDeviceFeatures2(physical_, &sup);

  VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f12.pNext = &f13;
  f2.pNext = &f12;
  f13.synchronization2 = VK_TRUE;
  f13.dynamicRendering = VK_TRUE;
  f13.maintenance4 = s13.maintenance4;
  f12.timelineSemaphore = VK_TRUE;
  f12.hostQueryReset = VK_TRUE;
  f12.scalarBlockLayout = s12.scalarBlockLayout;
  f12.shaderFloat16 = s12.shaderFloat16;
  f12.storageBuffer8BitAccess = s12.storageBuffer8BitAccess;
  f12.uniformAndStorageBuffer8BitAccess = s12.uniformAndStorageBuffer8BitAccess;
  f12.shaderInt8 = s12.shaderInt8;
  f12.bufferDeviceAddress = s12.bufferDeviceAddress;
  const VkPhysicalDeviceFeatures& s = sup.features;
  VkPhysicalDeviceFeatures& f = f2.features;
  f.textureCompressionBC = s.textureCompressionBC;
  f.shaderStorageImageWriteWithoutFormat = s.shaderStorageImageWriteWithoutFormat;
  f.shaderStorageImageReadWithoutFormat = s.shaderStorageImageReadWithoutFormat;
  f.shaderStorageImageExtendedFormats = s.shaderStorageImageExtendedFormats;
  f.samplerAnisotropy = s.samplerAnisotropy;
  f.fillModeNonSolid = s.fillModeNonSolid;
  f.shaderInt16 = s.shaderInt16;
  f.shaderInt64 = s.shaderInt64;
  f.shaderFloat64 = s.shaderFloat64;
  f.fragmentStoresAndAtomics = s.fragmentStoresAndAtomics;
  f.independentBlend = s.independentBlend;
  f.depthClamp = s.depthClamp;
  f.imageCubeArray = s.imageCubeArray;
  info_.texture_compression_bc = s.textureCompressionBC;
  info_.storage_image_write_without_format = s.shaderStorageImageWriteWithoutFormat;
  info_.sampler_anisotropy = s.samplerAnisotropy;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo q{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  q.queueFamilyIndex = queue_family_;
  q.queueCount = 1;
  q.pQueuePriorities = &priority;
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &f2;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &q;
  info.enabledExtensionCount = uint32_t(exts.size());
  info.ppEnabledExtensionNames = exts.data();
  VkResult r = vkCreateDevice(physical_, &info, nullptr, &device_);
  if (r != VK_SUCCESS) fail("gpu: vkCreateDevice on '%s' failed: %s", info_.name.c_str(), vk_result_name(r));
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  uint32_t qn = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, nullptr);
  std::vector<VkQueueFamilyProperties> qf(qn);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &qn, qf.data());
  info_.timestamps = qf[queue_family_].timestampValidBits > 0 && info_.limits.timestampPeriod > 0;

  if (info_.push_descriptors)
    cmd_push_descriptor_set = (PFN_vkCmdPushDescriptorSetKHR)vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR");
  if (!cmd_push_descriptor_set) info_.push_descriptors = false;

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT | VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = queue_family_;
  VK_CHECK(vkCreateCommandPool(device_, &pool, nullptr, &oneoff_pool_));
  VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VK_CHECK(vkCreateFence(device_, &fence, nullptr, &oneoff_fence_));
  set_name(queue_, "main queue");
  set_name(oneoff_pool_, "one-off command pool");

  LOG_INFO("gpu: %s (%s, %s), Vulkan %u.%u.%u%s", info_.name.c_str(), device_type_name(info_.type),
           info_.driver_info.c_str(), VK_API_VERSION_MAJOR(info_.api_version), VK_API_VERSION_MINOR(info_.api_version),
           VK_API_VERSION_PATCH(info_.api_version), validation_ ? ", validation on" : "");
}

void Context::set_name(VkObjectType type, uint64_t handle, const char* name) const {
  if (!set_name_fn_ || !handle || !device_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name;
  set_name_fn_(device_, &info);
}

void Context::cmd_begin_label(VkCommandBuffer cmd, const char* name, const float color[4]) const {
  if (!begin_label_fn_) return;
  VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  label.pLabelName = name;
  if (color) std::memcpy(label.color, color, sizeof label.color);
  begin_label_fn_(cmd, &label);
}

void Context::cmd_end_label(VkCommandBuffer cmd) const {
  if (end_label_fn_) end_label_fn_(cmd);
}

void Context::submit(const VkSubmitInfo2& info, VkFence fence) const {
  std::lock_guard lock(queue_mutex_);
  VK_CHECK(vkQueueSubmit2(queue_, 1, &info, fence));
}

static thread_local bool t_in_submit_and_wait = false;

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  // A nested call (e.g. Buffer::upload inside the record callback) would deadlock on the mutex.
  if (t_in_submit_and_wait) fail("gpu: submit_and_wait called from inside a submit_and_wait callback");
  std::lock_guard lock(oneoff_mutex_);
  t_in_submit_and_wait = true;
  struct Reset {
    ~Reset() { t_in_submit_and_wait = false; }
  } reset_flag;
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = oneoff_pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  VK_CHECK(vkAllocateCommandBuffers(device_, &ai, &cmd));
  struct FreeCmd {
    VkDevice d;
    VkCommandPool p;
    VkCommandBuffer c;
    ~FreeCmd() { vkFreeCommandBuffers(d, p, 1, &c); }
  } guard{device_, oneoff_pool_, cmd};
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(cmd, &bi));
  record(cmd);
  VK_CHECK(vkEndCommandBuffer(cmd));
  VkCommandBufferSubmitInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cbi.commandBuffer = cmd;
  VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  si.commandBufferInfoCount = 1;
  si.pCommandBufferInfos = &cbi;
  VK_CHECK(vkResetFences(device_, 1, &oneoff_fence_));
  submit(si, oneoff_fence_);
  VK_CHECK(vkWaitForFences(device_, 1, &oneoff_fence_, VK_TRUE, UINT64_MAX));
}

void Context::wait_idle() const {
  std::lock_guard lock(queue_mutex_);
  vkDeviceWaitIdle(device_);
}

}  // namespace cumulo::gpu
