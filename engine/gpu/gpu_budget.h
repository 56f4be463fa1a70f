#pragma once
// A GPU memory budget that makes the device look small (issue 25): $CUMULO_GPU_MEMORY_BUDGET_MB caps the device
// memory the process's allocators hand out (the sum of live suballocations, every memory type). An allocation that
// would pass it throws GpuBudgetError naming the resource, what it needs, what is in use and the budget; callers
// that can do with less catch it (the clouds draw the level without an asset that does not fit, and say so), the rest let it reach the
// command's one-line error. Host memory has its own budget (core/memory_budget.h, CUMULO_MEMORY_BUDGET_MB).
//
//   try { ... ctx.allocator().allocate(req, usage, "clouds.light_grid") ... }
//   catch (const gpu::GpuBudgetError& e) { LOG_WARN("%s: skipped", e.what()); }
#include <cstdint>
#include <string>

#include "engine/core/error.h"

namespace cumulo::gpu {

class GpuBudgetError : public Error {
 public:
  using Error::Error;
};

// The budget in bytes; 0 when none is set. Throws cumulo::Error for a value that is not a positive whole number of
// MiB (naming the variable).
uint64_t gpu_memory_budget_bytes();

}  // namespace cumulo::gpu
