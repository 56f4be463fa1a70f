#include "engine/gpu/gpu_budget.h"

#include <cstdlib>

#include "engine/core/message.h"

namespace cumulo::gpu {

uint64_t gpu_memory_budget_bytes() {
  const char* env = std::getenv("CUMULO_GPU_MEMORY_BUDGET_MB");
  if (!env || !*env) return 0;
  char* end = nullptr;
  const unsigned long long mb = std::strtoull(env, &end, 10);
  if (!*end && mb > 0 && mb < (1ull << 44)) return mb << 20;
  fail("CUMULO_GPU_MEMORY_BUDGET_MB: expected a positive number of MiB, got %s", quote(env).c_str());
}

}  // namespace cumulo::gpu
