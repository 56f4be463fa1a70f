#include "engine/gpu/detail/device_select.h"

#include <gtest/gtest.h>

#include "engine/core/error.h"

using namespace cumulo::gpu::detail;

static DeviceCandidate dev(const char* name, VkPhysicalDeviceType t, bool ok = true) {
  return {name, t, ok, ok ? "" : "Vulkan 1.3 not supported"};
}

TEST(DeviceSelect, PrefersDiscreteThenIntegratedThenCpu) {
  std::vector<DeviceCandidate> c = {dev("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                    dev("Intel UHD", VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU),
                                    dev("RTX 4090", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)};
  EXPECT_EQ(choose_device(c, ""), 2);
  c.pop_back();
  EXPECT_EQ(choose_device(c, ""), 1);
  c.pop_back();
  EXPECT_EQ(choose_device(c, ""), 0);
}

TEST(DeviceSelect, SkipsUnsuitable) {
  std::vector<DeviceCandidate> c = {dev("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                    dev("Old GPU", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false)};
  EXPECT_EQ(choose_device(c, ""), 0);
  c[0].suitable = false;
  EXPECT_THROW(choose_device(c, ""), cumulo::Error);
}

TEST(DeviceSelect, OverrideByIndexOrNameSubstring) {
  std::vector<DeviceCandidate> c = {dev("NVIDIA RTX", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
                                    dev("llvmpipe (LLVM 15)", VK_PHYSICAL_DEVICE_TYPE_CPU)};
  EXPECT_EQ(choose_device(c, "1"), 1);
  EXPECT_EQ(choose_device(c, "0"), 0);
  EXPECT_EQ(choose_device(c, "LLVMPIPE"), 1);
  EXPECT_EQ(choose_device(c, "rtx"), 0);
}

TEST(DeviceSelect, BadOverrideNamesTheSpecAndListsDevices) {
  std::vector<DeviceCandidate> c = {dev("llvmpipe", VK_PHYSICAL_DEVICE_TYPE_CPU),
                                    dev("Old", VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, false)};
  try {
    choose_device(c, "radeon");
    FAIL();
  } catch (const cumulo::Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("radeon"), std::string::npos);
    EXPECT_NE(m.find("llvmpipe"), std::string::npos);
  }
  EXPECT_THROW(choose_device(c, "7"), cumulo::Error);
  try {
    choose_device(c, "old");
    FAIL();
  } catch (const cumulo::Error& e) {
    EXPECT_NE(std::string(e.what()).find("unsuitable"), std::string::npos);
  }
}
