#pragma once
// Shared fixture for Vulkan tests: a fresh Context per test (validation on via CUMULO_VALIDATION=1
// from CTest), a private cache folder, and a zero-validation-error check after the Context is gone
// (so messages about leaked objects at vkDestroyDevice count too).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>

#include "engine/gpu/context.h"

namespace cumulo::gpu::test {

inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("cumulo_gpu_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A temp folder removed at scope exit; declare it before the Context that uses it as cache_dir
// (the Context writes its pipeline cache when destroyed).
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name) : path(temp_dir(name)) {}
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    errors_before_ = total_validation_errors();
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    cache_ = temp_dir(std::string(info->test_suite_name()) + "_" + info->name());
    ContextDesc desc;
    desc.validation = true;
    desc.cache_dir = cache_;
    ctx_ = std::make_unique<Context>(desc);
    ASSERT_TRUE(ctx_->validation_enabled()) << "VK_LAYER_KHRONOS_validation is required for gpu tests";
  }
  void TearDown() override {
    if (ctx_) {
      EXPECT_EQ(ctx_->validation_errors(), 0u) << ctx_->last_validation_message();
    }
    ctx_.reset();
    EXPECT_EQ(total_validation_errors(), errors_before_) << "validation errors while destroying the context";
    std::filesystem::remove_all(cache_);
  }
  Context& ctx() { return *ctx_; }

  std::unique_ptr<Context> ctx_;
  std::filesystem::path cache_;
  uint32_t errors_before_ = 0;
};

}  // namespace cumulo::gpu::test
