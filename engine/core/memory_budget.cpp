#include "engine/core/memory_budget.h"

#include <unistd.h>

#include <cstdlib>
#include <limits>

#include "engine/core/error.h"
#include "engine/core/message.h"

namespace cumulo {

uint64_t memory_budget_bytes() {
  if (const char* env = std::getenv("CUMULO_MEMORY_BUDGET_MB")) {
    char* end = nullptr;
    const unsigned long long mb = std::strtoull(env, &end, 10);
    if (*env && !*end && mb > 0 && mb < (1ull << 44)) return mb << 20;
    fail("CUMULO_MEMORY_BUDGET_MB: expected a positive number of MiB, got %s", quote(env).c_str());
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 8ull << 30;  // unknown: a modest machine
  return uint64_t(pages) * uint64_t(page) / 4 * 3;
}

void check_memory_budget(uint64_t bytes, const std::string& what) {
  const uint64_t budget = memory_budget_bytes();
  if (bytes <= budget) return;
  const double gib = double(1ull << 30);
  fail("%s needs about %.1f GiB, over the memory budget of %.1f GiB (set CUMULO_MEMORY_BUDGET_MB to change it)",
       what.c_str(), double(bytes) / gib, double(budget) / gib);
}

uint64_t saturating_product(std::initializer_list<uint64_t> factors) {
  uint64_t p = 1;
  for (uint64_t f : factors) {
    if (f != 0 && p > std::numeric_limits<uint64_t>::max() / f) return std::numeric_limits<uint64_t>::max();
    p *= f;
  }
  return p;
}

}  // namespace cumulo
