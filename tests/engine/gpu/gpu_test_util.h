#pragma once
// Shared fixture for Vulkan tests: a fresh Context per test (validation on via CUMULO_VALIDATION=1
// from CTest), a private cache folder, and a zero-validation-error check after the Context is gone
// (so messages about leaked objects at vkDestroyDevice count too).
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "engine/gpu/context.h"
#include "tests/support/temp_dir.h"

namespace cumulo::gpu::test {

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    errors_before_ = total_validation_errors();
    cache_ = cumulo::test::fresh_temp_dir(cumulo::test::test_temp_name("cumulo_gpu"));
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
