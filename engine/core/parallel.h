#pragma once
// parallel_for over [0, count) on all hardware threads (or CUMULO_THREADS), in contiguous chunks.
// The body must be safe to call concurrently for different indices. Exceptions propagate.
#include <cstddef>
#include <functional>

namespace cumulo {

unsigned worker_count();
void parallel_for(size_t count, const std::function<void(size_t begin, size_t end)>& body, size_t min_chunk = 1);

}  // namespace cumulo
